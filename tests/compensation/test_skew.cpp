// Firmware skew targets: factors against docs/conventions.md, files read back by the test's own
// readers, the firmware's rule applied to the model, Klipper's diagonal formula, bad input.
// RepRapFirmware M556 and FluidNC Skewed: the rules written again here from the firmware source
// (RepRapFirmware src/Movement/Move.cpp AxisTransform(), FluidNC PR #849 GenericCartesian.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <regex>
#include <sstream>

#include "mtcal/compensation/skew.hpp"
#include "mtcal/io/compensation/firmware.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::vmc;

std::string text_of(const TargetOutput& out, const std::string& name) {
  for (const auto& f : out.files)
    if (f.name == name) return f.text;
  ADD_FAILURE() << "no " << name;
  return "";
}

double number_after(const std::string& text, const std::string& key) {
  std::smatch m;
  const std::regex re(key + R"(\s*([-+0-9.eE]+))");
  EXPECT_TRUE(std::regex_search(text, m, re)) << key << " in " << text;
  return m.empty() ? NAN : std::stod(m[1]);
}

// vmc-3axis.yaml: EC0Y 15 um/m, EB0Z 20 um/m, EA0Z -12 um/m. docs/conventions.md: EC0Y > 0 turns
// Y from +y towards -x (e_x = -EC0Y y), EB0Z moves the tool by -0.4 um in x per urad at Z = -400
// (e_x = EB0Z z), EA0Z by +0.4 um in y (e_y = -EA0Z z).
TEST(SkewTarget, FactorsAreTheSquarenessByHand) {
  const auto c = compensate_skew(vmc(), {}, "marlin");
  EXPECT_NEAR(c.factors.xy, -15e-6, 1e-12);
  EXPECT_NEAR(c.factors.xz, 20e-6, 1e-12);
  EXPECT_NEAR(c.factors.yz, 12e-6, 1e-12);
}

TEST(SkewTarget, FilesReadBackAndTheFirmwareRuleRemovesTheSquareness) {
  Machine m = vmc();
  m.keep_only({"EC0Y", "EB0Z", "EA0Z"});
  const auto c = compensate_skew(m, {}, "klipper");
  const TargetOutput k = klipper_output(c);
  const std::string cfg = text_of(k, "skew.cfg");
  EXPECT_NE(cfg.find("[skew_correction mtcal]"), std::string::npos);
  const SkewFactors read{number_after(cfg, "xy_skew:"), number_after(cfg, "xz_skew:"), number_after(cfg, "yz_skew:")};
  const std::string gcode = text_of(marlin_output(c), "marlin.gcode");
  EXPECT_NEAR(number_after(gcode, "M852 I"), read.xy, 1e-12);
  EXPECT_NEAR(number_after(gcode, " J"), read.xz, 1e-12);
  EXPECT_NEAR(number_after(gcode, " K"), read.yz, 1e-12);
  // The firmware commands calc_skew(programmed); the model says where the tool lands.
  const ErrorModel model(m);
  double worst = 0.0;
  for (double x : {-400.0, 0.0, 400.0})
    for (double y : {-250.0, 250.0})
      for (double z : {-500.0, 0.0}) {
        const Vec3 p(x, y, z);
        const Vec3 cmd = skew_command(read, p);
        const std::vector<double> q{cmd.x(), cmd.y(), cmd.z()};
        const Vec3 reached = cmd + model.evaluate(q).translation;
        worst = std::max(worst, (reached - p).norm());
        EXPECT_NEAR((skew_reached(read, cmd) - p).norm(), 0.0, 1e-12);  // calc_unskew inverts calc_skew
      }
  // A shear holds a rotation of the axis lines to first order: what is left is of the order of the
  // angle squared times the distance, (2e-5)^2 * 707 mm = 2.8e-7 mm at the corners of the travel.
  EXPECT_LT(worst, 3e-7);
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
  EXPECT_TRUE(c.summary.not_compensated.empty());
}

// klippy/extras/skew_correction.py, calc_skew_factor(ac, bd, ad), written again here.
double klipper_calc_skew_factor(double ac, double bd, double ad) {
  const double side = std::sqrt(2 * ac * ac + 2 * bd * bd - 4 * ad * ad) / 2.0;
  return std::tan(M_PI / 2 - std::acos((ac * ac - side * side - ad * ad) / (2 * side * ad)));
}

TEST(SkewTarget, KlipperDiagonalsGiveTheFactorBack) {
  for (double k : {-15e-6, 0.0, 2e-5, 1e-3, -0.05}) {
    const auto l = klipper_skew_lengths(k);
    EXPECT_NEAR(klipper_calc_skew_factor(l[0], l[1], l[2]), k, 1e-12) << k;
  }
  const std::string g = text_of(klipper_output(compensate_skew(vmc(), {}, "klipper")), "skew.gcode");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(g, m, std::regex(R"(XY=([0-9.]+),([0-9.]+),([0-9.]+))")));
  EXPECT_NEAR(klipper_calc_skew_factor(std::stod(m[1]), std::stod(m[2]), std::stod(m[3])), -15e-6, 1e-9);
}

TEST(SkewTarget, BadInputIsRefused) {
  const Machine five = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  EXPECT_THROW(compensate_skew(five, {}, "klipper"), InputError);
  Machine m = vmc();
  m.keep_only({"EXX"});
  try {
    compensate_skew(m, {}, "marlin");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no squareness"), std::string::npos) << e.what();
  }
}

// The RepRapFirmware rule, written again from Move::AxisTransform() (compensateXY = true) with
// GCodes2.cpp case 556 (tangents[0] = X/S is tanXY, tangents[1] = Y/S tanYZ, tangents[2] = Z/S tanXZ).
struct ReadM556 {
  double s = NAN, x = NAN, y = NAN, z = NAN, p = NAN;
};
ReadM556 read_m556(const std::string& text) {
  ReadM556 r;
  std::istringstream in(text);
  std::string line;
  int commands = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == ';') continue;
    std::istringstream words(line);
    std::string w;
    words >> w;
    EXPECT_EQ(w, "M556") << line;
    ++commands;
    while (words >> w) {
      const double v = std::stod(w.substr(1));
      switch (w[0]) {
        case 'S': r.s = v; break;
        case 'X': r.x = v; break;
        case 'Y': r.y = v; break;
        case 'Z': r.z = v; break;
        case 'P': r.p = v; break;
        default: ADD_FAILURE() << "unexpected word " << w;
      }
    }
  }
  EXPECT_EQ(commands, 1);
  return r;
}
Vec3 rrf_axis_transform(const ReadM556& m, const Vec3& user) {
  EXPECT_EQ(m.p, 0.0);  // P <= 0: compensateXY, the X coordinate takes tanXY * Y
  Vec3 machine = user;
  machine.x() += m.x / m.s * user.y() + m.z / m.s * user.z();
  machine.y() += m.y / m.s * user.z();
  return machine;
}

// The FluidNC rule, written again from Skewed::init() and Mtx::transform(): row i (axis section i)
// = offset_<j>_mm / distance_mm + identity, motor_j = sum_i p_i row_i[j].
std::map<std::string, std::map<std::string, double>> read_fluidnc(const std::string& text) {
  std::map<std::string, std::map<std::string, double>> sections;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> path;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t indent = line.find_first_not_of(' ');
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) {
      ADD_FAILURE() << "not a YAML key: " << line;
      continue;
    }
    const std::string key = line.substr(indent, colon - indent);
    const std::string value = line.substr(colon + 1);
    if (value.empty()) {
      path.resize(indent / 2);
      path.push_back(key);
      continue;
    }
    EXPECT_EQ(path.size(), 3u) << line;
    EXPECT_EQ(path[0], "kinematics");
    EXPECT_EQ(path[1], "Skewed");
    sections[path[2]][key] = std::stod(value);
  }
  return sections;
}
Vec3 fluidnc_transform(const std::map<std::string, std::map<std::string, double>>& s, const Vec3& p) {
  const char* names[] = {"x", "y", "z"};
  Vec3 motors = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    const auto& sec = s.at(names[i]);
    for (int j = 0; j < 3; ++j)
      motors[j] += p[i] * (sec.at(std::string("offset_") + names[j] + "_mm") / sec.at("distance_mm") + (i == j));
  }
  return motors;
}

// The error the firmware holds at a commanded point: the position it was asked for less the
// command (the rule is linear and triangular: solved from z down).
Vec3 implied_error(const std::function<Vec3(const Vec3&)>& rule, const Vec3& command) {
  Vec3 p = command;
  for (int it = 0; it < 50; ++it) p += command - rule(p);  // fixed point: |T| ~ 1e-5
  return p - command;
}

TEST(SkewTarget, RrfAndFluidncSignsByHand) {
  // vmc-3axis: e_x = -EC0Y y = -15e-6 y, so RepRapFirmware must command x + 15e-6 y: over S = 100
  // mm, X = +0.0015; Y = -yz S = -0.0012; Z = (xy yz - xz) S = (-15e-6 * 12e-6 - 20e-6) * 100.
  const auto c = compensate_skew(vmc(), {}, "rrf");
  const ReadM556 m = read_m556(text_of(rrf_output(c), "rrf.gcode"));
  EXPECT_EQ(m.s, 100.0);
  EXPECT_NEAR(m.x, 0.0015, 1e-12);
  EXPECT_NEAR(m.y, -0.0012, 1e-12);
  EXPECT_NEAR(m.z, -0.002000018, 1e-12);
  EXPECT_EQ(c.summary.quantity, TableQuantity::Correction);
  CompensationOptions o;
  o.skew_reference_length = 250;
  const auto f = read_fluidnc(text_of(fluidnc_output(compensate_skew(vmc(), o, "fluidnc")), "fluidnc-kinematics.yaml"));
  EXPECT_EQ(f.at("y").at("distance_mm"), 250.0);
  EXPECT_NEAR(f.at("y").at("offset_x_mm"), 15e-6 * 250, 1e-12);
  EXPECT_NEAR(f.at("z").at("offset_y_mm"), -12e-6 * 250, 1e-12);
  EXPECT_EQ(f.at("x").at("offset_y_mm"), 0.0);
}

// Round trip: the files read back, the firmware's rule applied, the model's squareness error
// recovered along the axis lines, where a shear holds it exactly (the model's error components
// there are first order in the angles; elsewhere the shear differs by angle^2 x distance).
TEST(SkewTarget, RrfAndFluidncRoundTripRecoverTheModelError) {
  Machine m = vmc();
  m.keep_only({"EC0Y", "EB0Z", "EA0Z"});
  const ErrorModel model(m);
  CompensationOptions o;
  o.skew_reference_length = 137.5;
  const ReadM556 m556 = read_m556(text_of(rrf_output(compensate_skew(m, o, "rrf")), "rrf.gcode"));
  const auto fl = read_fluidnc(text_of(fluidnc_output(compensate_skew(m, o, "fluidnc")), "fluidnc-kinematics.yaml"));
  const std::function<Vec3(const Vec3&)> rules[] = {[&](const Vec3& p) { return rrf_axis_transform(m556, p); },
                                                    [&](const Vec3& p) { return fluidnc_transform(fl, p); }};
  const Vec3 e0 = model.evaluate(std::vector<double>{0, 0, 0}).translation;
  for (const auto& rule : rules) {
    for (double y : {-250.0, -100.0, 130.0, 250.0}) {
      const Vec3 e = model.evaluate(std::vector<double>{0, y, 0}).translation - e0;
      EXPECT_NEAR(implied_error(rule, {0, y, 0}).x(), e.x(), 1e-9) << y;
    }
    for (double z : {-500.0, -250.0, -40.0}) {
      const Vec3 e = model.evaluate(std::vector<double>{0, 0, z}).translation - e0;
      const Vec3 held = implied_error(rule, {0, 0, z});
      EXPECT_NEAR(held.x(), e.x(), 1e-9) << z;
      EXPECT_NEAR(held.y(), e.y(), 1e-9) << z;
    }
    // Commanded by the firmware, the tool lands where programmed up to the shear/rotation difference.
    double worst = 0.0;
    for (double x : {-400.0, 400.0})
      for (double y : {-250.0, 250.0})
        for (double z : {-500.0, 0.0}) {
          const Vec3 p(x, y, z), cmd = rule(p);
          worst = std::max(
              worst,
              (cmd + model.evaluate(std::vector<double>{cmd.x(), cmd.y(), cmd.z()}).translation - e0 - p).norm());
        }
    EXPECT_LT(worst, 3e-7);
  }
  for (const char* t : {"rrf", "fluidnc"}) {
    const auto c = compensate_skew(m, o, t);
    EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before) << t;
    EXPECT_TRUE(c.summary.not_compensated.empty()) << t;
  }
}

TEST(SkewTarget, RrfAndFluidncBadInput) {
  CompensationOptions o;
  o.skew_reference_length = 0.0;
  EXPECT_THROW(compensate_skew(vmc(), o, "rrf"), InputError);
  EXPECT_NO_THROW(compensate_skew(vmc(), o, "klipper"));  // Klipper's factors have no reference length
  EXPECT_THROW(compensate_skew(vmc(), {}, "grbl"), ModelError);
  o.skew_reference_length = 0.5;  // FluidNC: distance_mm from 1 mm
  EXPECT_THROW(compensate_skew(vmc(), o, "fluidnc"), InputError);
  EXPECT_NO_THROW(compensate_skew(vmc(), o, "rrf"));
  const Machine five = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  EXPECT_THROW(compensate_skew(five, {}, "fluidnc"), InputError);
  const auto c = compensate_skew(vmc(), {}, "fluidnc");
  ASSERT_FALSE(c.summary.warnings.empty());
  EXPECT_NE(c.summary.warnings[0].find("#849"), std::string::npos);
  const std::string yaml = text_of(fluidnc_output(c), "fluidnc-kinematics.yaml");
  EXPECT_NE(yaml.find("NEEDS A FLUIDNC BUILD"), std::string::npos);
}

}  // namespace
}  // namespace mtcal
