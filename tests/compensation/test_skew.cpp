// Firmware skew targets: factors against docs/conventions.md, files read back by the test's own
// readers, the firmware's rule applied to the model, Klipper's diagonal formula, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "mtcal/compensation/skew.hpp"
#include "mtcal/io/compensation_firmware.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

Machine vmc() { return load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml"); }

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

}  // namespace
}  // namespace mtcal
