// Siemens EEC target: AX_EEC.INI read back by the test's own reader, the control's rule applied
// (the axis moves by -value), the model's error recovered at the points; limits and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <sstream>

#include "mtcal/compensation/siemens.hpp"
#include "mtcal/io/compensation_siemens.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

Machine vmc() { return load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml"); }

struct EecTable {
  std::map<int, double> values;
  double step = NAN, min = NAN, max = NAN;
};

// The test's reader: %_N_AX_EEC_INI first, assignments $NAME[...]=value, ';' comments, M17 last.
std::map<std::string, EecTable> read_eec(const std::string& text) {
  std::map<std::string, EecTable> out;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "%_N_AX_EEC_INI");
  const std::regex value(R"(^\$AA_ENC_COMP\[0,(\d+),(AX\d+)\]=(-?[0-9.]+)$)");
  const std::regex param(R"(^\$AA_ENC_COMP_(STEP|MIN|MAX|IS_MODULO)\[0,(AX\d+)\]=(-?[0-9.]+)$)");
  std::string last;
  while (std::getline(in, line)) {
    std::smatch m;
    if (line.empty() || line[0] == ';' || line == "CHANDATA(1)") continue;
    last = line;
    if (std::regex_match(line, m, value)) {
      out[m[2]].values[std::stoi(m[1])] = std::stod(m[3]);
    } else if (std::regex_match(line, m, param)) {
      auto& t = out[m[2]];
      const double v = std::stod(m[3]);
      if (m[1] == "STEP") t.step = v;
      if (m[1] == "MIN") t.min = v;
      if (m[1] == "MAX") t.max = v;
      if (m[1] == "IS_MODULO") {
        EXPECT_EQ(v, 0.0);
      }
    } else if (line != "M17") {
      ADD_FAILURE() << "unexpected line " << line;
    }
  }
  EXPECT_EQ(last, "M17");
  return out;
}

double mean_error_along(const ErrorModel& model, std::size_t axis, double q) {
  std::vector<double> qs(model.axis_count(), 0.0);
  std::vector<std::int8_t> d(model.axis_count(), 0);
  qs[axis] = q;
  double sum = 0.0;
  for (int dir : {+1, -1}) {
    d[axis] = static_cast<std::int8_t>(dir);
    sum += model.evaluate(qs, d).translation.dot(model.machine().axes[axis].direction());
  }
  return sum / 2;
}

TEST(SiemensTarget, TablesReadBackGiveTheModelErrorAtThePoints) {
  const Machine m = vmc();
  const ErrorModel model(m);
  CompensationOptions o;
  o.points = 17;
  const auto tables = read_eec(siemens_output(compensate_siemens(m, o)).files.at(0).text);
  ASSERT_EQ(tables.size(), 3u);
  for (std::size_t a = 0; a < 3; ++a) {
    const EecTable& t = tables.at("AX" + std::to_string(a + 1));
    ASSERT_EQ(t.values.size(), 17u);
    EXPECT_NEAR(t.min + 16 * t.step, t.max, 1e-9);
    for (const auto& [i, v] : t.values) {
      const double q = t.min + i * t.step;
      // The value is the error: the control moves the axis by -value.
      EXPECT_NEAR(v, mean_error_along(model, a, q), 1e-9) << a << " " << q;
    }
  }
}

TEST(SiemensTarget, PositioningWithoutReversalLeavesUnderOnePercent) {
  Machine m = vmc();
  m.keep_only({"EXX", "EZZ"});  // polynomials; EYY is a table with its own backward run
  for (const char* p : {"EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);
  const auto c = compensate_siemens(m, {});
  EXPECT_TRUE(c.summary.not_compensated.empty());
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
  EXPECT_EQ(c.summary.quantity, TableQuantity::Error);
}

TEST(SiemensTarget, ReversalIsListedAsNotHeld) {
  const auto c = compensate_siemens(vmc(), {});
  bool reversal = false;
  for (const auto& n : c.summary.not_compensated)
    if (n.what.rfind("reversal", 0) == 0) {
      reversal = true;
      EXPECT_NEAR(n.max_error, 1e-3, 1e-9);  // EXX.b = 1 um: half of forward - reverse = 2 um
    }
  EXPECT_TRUE(reversal);
}

TEST(SiemensTarget, LimitsAndNothingToCompensate) {
  CompensationOptions o;
  o.points = 201;
  EXPECT_THROW(compensate_siemens(vmc(), o), InputError);
  Machine none = vmc();
  none.clear_errors();
  EXPECT_THROW(compensate_siemens(none, {}), InputError);
}

}  // namespace
}  // namespace mtcal
