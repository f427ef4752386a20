// LinuxCNC target: files read back by an independent reader, LinuxCNC's documented rule applied,
// the model's error recovered; limits and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "mtcal/compensation/linuxcnc.hpp"
#include "mtcal/io/compensation/linuxcnc.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

const TargetFile& linuxcnc_file_named(const TargetOutput& out, const std::string& name) {
  for (const auto& f : out.files)
    if (f.name == name) return f;
  throw std::runtime_error("no file " + name);
}

// The test's own reader of a COMP_FILE: three numbers a line, as usrmotLoadComp() reads it.
struct Rows {
  std::vector<double> nominal, forward, reverse;
};
Rows read_comp(const std::string& text) {
  Rows r;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    double a, b, c;
    std::string rest;
    EXPECT_TRUE(static_cast<bool>(ls >> a >> b >> c)) << line;
    EXPECT_FALSE(static_cast<bool>(ls >> rest)) << line;
    r.nominal.push_back(a);
    r.forward.push_back(b);
    r.reverse.push_back(c);
  }
  return r;
}

// The tool point's error along X when X alone moves (the others at 0), straight from the model.
double error_along(const ErrorModel& model, std::size_t axis, double q, int dir) {
  std::vector<double> qs(model.axis_count(), 0.0);
  std::vector<std::int8_t> d(model.axis_count(), 0);
  qs[axis] = q;
  d[axis] = static_cast<std::int8_t>(dir);
  return model.evaluate(qs, d).translation.dot(model.machine().axes[axis].direction());
}

TEST(LinuxcncTarget, BothTypesRecoverTheModelErrorAtTheNodes) {
  const Machine m = example("vmc-3axis.yaml");
  const ErrorModel model(m);
  for (int type : {0, 1}) {
    CompensationOptions o;
    o.points = 21;
    o.comp_file_type = type;
    const TargetOutput out = linuxcnc_output(compensate_linuxcnc(m, o));
    const std::string ini = linuxcnc_file_named(out, "linuxcnc.ini").text;
    for (std::size_t a = 0; a < 3; ++a) {
      const char letter = "XYZ"[a];
      EXPECT_NE(ini.find(fmt::format("[JOINT_{}]\nCOMP_FILE = {}.comp\nCOMP_FILE_TYPE = {}", a, letter, type)),
                std::string::npos)
          << ini;
      const Rows r = read_comp(linuxcnc_file_named(out, std::string(1, letter) + ".comp").text);
      ASSERT_EQ(r.nominal.size(), 21u);
      for (std::size_t i = 0; i < r.nominal.size(); ++i) {
        if (i > 0) {
          EXPECT_GT(r.nominal[i], r.nominal[i - 1]);
        }
        // usrmotLoadComp(): type 0 adds nominal - column, type 1 the column; a correction is -e.
        const double cf = type == 0 ? r.nominal[i] - r.forward[i] : r.forward[i];
        const double cr = type == 0 ? r.nominal[i] - r.reverse[i] : r.reverse[i];
        EXPECT_NEAR(-cf, error_along(model, a, r.nominal[i], +1), 1e-9) << letter << r.nominal[i];
        EXPECT_NEAR(-cr, error_along(model, a, r.nominal[i], -1), 1e-9) << letter << r.nominal[i];
      }
      // The table spans the travel (vmc-3axis.yaml: X -400..400, Y -250..250, Z -500..0).
      const double lo[3] = {-400, -250, -500}, hi[3] = {400, 250, 0};
      EXPECT_DOUBLE_EQ(r.nominal.front(), lo[a]);
      EXPECT_DOUBLE_EQ(r.nominal.back(), hi[a]);
    }
    EXPECT_EQ(out.summary.quantity, type == 0 ? TableQuantity::ActualPosition : TableQuantity::Correction);
  }
}

TEST(LinuxcncTarget, PositioningOnlyModelLeavesUnderOnePercent) {
  Machine m = example("vmc-3axis.yaml");
  m.keep_only({"EXX", "EYY", "EZZ"});
  CompensationOptions o;
  const auto c = compensate_linuxcnc(m, o);
  EXPECT_TRUE(c.summary.not_compensated.empty());
  EXPECT_GT(c.summary.residual.max_norm_before, 5e-3);
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
  EXPECT_LT(c.summary.residual.va_after, 0.01 * c.summary.residual.va_before);
}

TEST(LinuxcncTarget, FullModelListsWhatTablesCannotHold) {
  const auto c = compensate_linuxcnc(example("vmc-3axis.yaml"), {});
  bool squareness = false;
  for (const auto& n : c.summary.not_compensated) {
    squareness = squareness || n.what == "EC0Y";
    EXPECT_NE(n.what, "EXX");
    EXPECT_GE(n.max_error, 0.0);
  }
  EXPECT_TRUE(squareness);
  EXPECT_LT(c.summary.residual.max_norm_after, c.summary.residual.max_norm_before);
}

// hu40t-wCBXfYZt.yaml: C on B on the table -> xyzbc-trt-kins; EX0C = 3 um, EY0C = -4 um.
TEST(LinuxcncTarget, TrtPinsFromTheRotaryAxisLines) {
  const Machine m = example("hu40t-wCBXfYZt.yaml");
  const auto c = compensate_linuxcnc(m, {});
  EXPECT_EQ(c.kinematics, "xyzbc-trt-kins");
  EXPECT_EQ(c.coordinates, "XYZBC");
  const TargetOutput out = linuxcnc_output(c);
  const std::string hal = linuxcnc_file_named(out, "linuxcnc-kins.hal").text;
  EXPECT_NE(hal.find("setp xyzbc-trt-kins.x-rot-point 0.003000000\n"), std::string::npos) << hal;
  EXPECT_NE(hal.find("setp xyzbc-trt-kins.y-rot-point -0.004000000\n"), std::string::npos) << hal;
  const std::string ini = linuxcnc_file_named(out, "linuxcnc.ini").text;
  EXPECT_NE(ini.find("HALFILE = linuxcnc-kins.hal"), std::string::npos);
  EXPECT_NE(ini.find("COORDINATES = X Y Z B C"), std::string::npos);
}

TEST(LinuxcncTarget, BadInputIsRefusedNamingTheItem) {
  const Machine m = example("vmc-3axis.yaml");
  CompensationOptions o;
  o.comp_file_type = 2;
  EXPECT_THROW(compensate_linuxcnc(m, o), InputError);
  o = {};
  o.points = 257;  // EMCMOT_COMP_SIZE is 256
  try {
    compensate_linuxcnc(m, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("256"), std::string::npos) << e.what();
  }
  o = {};
  o.sampling = {{'X', -500.0, 400.0, 11}};  // beyond X's travel
  try {
    compensate_linuxcnc(m, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "X");
  }
  o = {};
  o.sampling = {{'Q', 0.0, 1.0, 11}};
  EXPECT_THROW(compensate_linuxcnc(m, o), InputError);
  Machine none = m;
  none.clear_errors();
  try {
    compensate_linuxcnc(none, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to compensate"), std::string::npos);
  }
}

}  // namespace
}  // namespace mtcal
