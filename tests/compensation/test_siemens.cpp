// Siemens EEC/CEC target: AX_EEC.INI and NC_CEC.INI read back by the test's own readers, the
// control's rule applied (EEC: the axis moves by -value; CEC: the output axis by +value, tables
// summed, linear interpolation, ends held), the model's error recovered at the points; limits and
// bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <regex>
#include <sstream>

#include "mtcal/compensation/siemens.hpp"
#include "mtcal/io/compensation/siemens.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::vmc;

// The part of vmc-3axis that EEC and CEC hold: positioning, straightness and squareness of X, Y, Z
// (the tables are sampled on these alone; the angular errors are listed as not held).
Machine vmc_held_part() {
  Machine m = vmc();
  m.keep_only({"EXX", "EYY", "EZZ", "EYX", "EZX", "EXY", "EZY", "EXZ", "EYZ", "EC0Y", "EA0Z", "EB0Z"});
  return m;
}

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

double siemens_mean_error_along(const ErrorModel& model, std::size_t axis, double q) {
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
  const ErrorModel model(vmc_held_part());
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
      EXPECT_NEAR(v, siemens_mean_error_along(model, a, q), 1e-9) << a << " " << q;
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

struct CecTable {
  std::map<int, double> values;
  std::string input, output;
  double step = NAN, min = NAN, max = NAN, direction = NAN, mult = NAN, modulo = NAN;
};

// The test's reader: %_N_NC_CEC_INI first, $AN_CEC[t,i]=value, $AN_CEC_<PARAM>[t]=value or =(AXn),
// ';' comments, CHANDATA(1), M17 last.
std::map<int, CecTable> read_cec(const std::string& text) {
  std::map<int, CecTable> out;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "%_N_NC_CEC_INI");
  const std::regex value(R"(^\$AN_CEC\[(\d+),(\d+)\]=(-?[0-9.]+)$)");
  const std::regex axis(R"(^\$AN_CEC_(INPUT|OUTPUT)_AXIS\[(\d+)\]=\((AX\d+)\)$)");
  const std::regex param(R"(^\$AN_CEC_(STEP|MIN|MAX|DIRECTION|MULT_BY_TABLE|IS_MODULO)\[(\d+)\]=(-?[0-9.]+)$)");
  std::string last;
  while (std::getline(in, line)) {
    std::smatch m;
    if (line.empty() || line[0] == ';' || line == "CHANDATA(1)") continue;
    last = line;
    if (std::regex_match(line, m, value)) {
      out[std::stoi(m[1])].values[std::stoi(m[2])] = std::stod(m[3]);
    } else if (std::regex_match(line, m, axis)) {
      (m[1] == "INPUT" ? out[std::stoi(m[2])].input : out[std::stoi(m[2])].output) = m[3];
    } else if (std::regex_match(line, m, param)) {
      auto& t = out[std::stoi(m[2])];
      const double v = std::stod(m[3]);
      if (m[1] == "STEP") t.step = v;
      if (m[1] == "MIN") t.min = v;
      if (m[1] == "MAX") t.max = v;
      if (m[1] == "DIRECTION") t.direction = v;
      if (m[1] == "MULT_BY_TABLE") t.mult = v;
      if (m[1] == "IS_MODULO") t.modulo = v;
    } else if (line != "M17") {
      ADD_FAILURE() << "unexpected line " << line;
    }
  }
  EXPECT_EQ(last, "M17");
  return out;
}

// Linear interpolation between the nodes min + i step, the end values held (K3 4.4.3: "the
// compensation value of interpolation point 0 is used for all positions smaller than the initial
// position"), written again here.
double table_value(const std::map<int, double>& values, double min, double step, double x) {
  const int last = values.rbegin()->first;
  const double u = (x - min) / step;
  if (u <= 0) return values.at(0);
  if (u >= last) return values.at(last);
  const int i = static_cast<int>(std::floor(u));
  return values.at(i) + (u - i) * (values.at(i + 1) - values.at(i));
}

// What the control adds to each machine axis AX1..AX3 at a configuration q (X, Y, Z order).
std::array<double, 3> control_correction(const std::map<std::string, EecTable>& eec, const std::map<int, CecTable>& cec,
                                         const std::array<double, 3>& q) {
  std::array<double, 3> c{};
  for (const auto& [ax, t] : eec) {
    const int a = std::stoi(ax.substr(2)) - 1;
    c[a] -= table_value(t.values, t.min, t.step, q[a]);  // EEC values are errors
  }
  for (const auto& [index, t] : cec) {
    EXPECT_EQ(t.direction, 0.0);
    EXPECT_EQ(t.mult, 0.0);
    EXPECT_EQ(t.modulo, 0.0);
    const int in = std::stoi(t.input.substr(2)) - 1, to = std::stoi(t.output.substr(2)) - 1;
    c[to] += table_value(t.values, t.min, t.step, q[in]);  // CEC values are corrections
  }
  return c;
}

// The model's error (mean of both directions, as one table holds it) at q.
Vec3 mean_error(const ErrorModel& model, const std::array<double, 3>& q) {
  const std::vector<double> qs(q.begin(), q.end());
  Vec3 sum = Vec3::Zero();
  for (std::int8_t dir : {std::int8_t{1}, std::int8_t{-1}})
    sum += model.evaluate(qs, std::vector<std::int8_t>(3, dir)).translation;
  return sum / 2;
}

TEST(SiemensTarget, CrossTablesReadBackGiveTheModelErrorAlongEachAxisLine) {
  const Machine m = vmc();
  const ErrorModel model(vmc_held_part());
  CompensationOptions o;
  o.points = 17;  // X every 50 mm, Y and Z every 31.25 mm: 0 (the reference) is a node of each
  const TargetOutput out = siemens_output(compensate_siemens(m, o));
  ASSERT_EQ(out.files.size(), 2u);
  EXPECT_EQ(out.files[1].name, "NC_CEC.INI");
  const auto eec = read_eec(out.files[0].text);
  const auto cec = read_cec(out.files[1].text);
  // vmc-3axis has straightness or squareness between every pair of X, Y, Z: six tables.
  ASSERT_EQ(cec.size(), 6u);
  std::map<std::pair<std::string, std::string>, int> pairs;
  for (const auto& [t, table] : cec) {
    ++pairs[{table.input, table.output}];
    ASSERT_EQ(table.values.size(), 17u);
    EXPECT_NEAR(table.min + 16 * table.step, table.max, 1e-9);
  }
  EXPECT_EQ(pairs.size(), 6u);
  // Along each axis line through the reference (the others at 0), the control's corrections
  // cancel the model's error on every axis at every node, to the file's 1e-9 mm.
  for (int a = 0; a < 3; ++a) {
    const EecTable& t = eec.at("AX" + std::to_string(a + 1));
    for (const auto& [i, v] : t.values) {
      std::array<double, 3> q{0, 0, 0};
      q[a] = t.min + i * t.step;
      const auto c = control_correction(eec, cec, q);
      const Vec3 e = mean_error(model, q);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(c[k], -e[k], 1.5e-9) << "axis " << a << " at " << q[a] << ", output " << k;
    }
  }
}

TEST(SiemensTarget, StraightnessSquarenessAndPositioningLeaveUnderOnePercent) {
  Machine m = vmc();
  // Everything EEC + CEC hold: positioning (polynomials, no reversal), straightness, squareness.
  m.keep_only({"EXX", "EZZ", "EYX", "EZX", "EXY", "EZY", "EXZ", "EYZ", "EC0Y", "EA0Z", "EB0Z"});
  for (const char* p : {"EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);
  const auto c = compensate_siemens(m, {});
  EXPECT_TRUE(c.summary.not_compensated.empty());
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
  // The same from the files with the test's rule over a 5 x 5 x 5 grid (both directions), and
  // with the EEC file alone, which leaves the cross errors.
  const TargetOutput out = siemens_output(c);
  const auto eec = read_eec(out.files.at(0).text);
  const auto cec = read_cec(out.files.at(1).text);
  const ErrorModel model(m);
  double before = 0, after = 0, eec_alone = 0;
  for (double x : {-400.0, -170.0, 0.0, 230.0, 400.0})
    for (double y : {-250.0, -90.0, 0.0, 110.0, 250.0})
      for (double z : {-500.0, -333.0, -250.0, -60.0, 0.0})
        for (std::int8_t dir : {std::int8_t{1}, std::int8_t{-1}}) {
          const std::array<double, 3> q{x, y, z};
          const auto cc = control_correction(eec, cec, q), ce = control_correction(eec, {}, q);
          const std::vector<std::int8_t> d(3, dir);
          const Vec3 nominal_error = model.evaluate(std::vector<double>{x, y, z}, d).translation;
          const std::vector<double> qc{x + cc[0], y + cc[1], z + cc[2]}, qe{x + ce[0], y + ce[1], z + ce[2]};
          // Commanded q + c, the tool lands at q + c + e(q + c); the program asked for q.
          const Vec3 ra = Vec3(cc[0], cc[1], cc[2]) + model.evaluate(qc, d).translation;
          const Vec3 re = Vec3(ce[0], ce[1], ce[2]) + model.evaluate(qe, d).translation;
          before = std::max(before, nominal_error.norm());
          after = std::max(after, ra.norm());
          eec_alone = std::max(eec_alone, re.norm());
        }
  EXPECT_LT(after, 0.01 * before);
  EXPECT_GT(eec_alone, 0.2 * before);
}

TEST(SiemensTarget, AngularErrorsAreListedAsNotHeld) {
  const auto c = compensate_siemens(vmc(), {});
  std::vector<std::string> names;
  for (const auto& n : c.summary.not_compensated) names.push_back(n.what);
  for (const char* held : {"EXX", "EYX", "EC0Y", "EB0Z", "EA0Z"})
    EXPECT_EQ(std::count(names.begin(), names.end(), held), 0) << held;
  for (const char* not_held : {"EAX", "EBY", "ECZ"})
    EXPECT_EQ(std::count(names.begin(), names.end(), not_held), 1) << not_held;
}

TEST(SiemensTarget, TooManyCrossTablesOrPointsAreRefused) {
  CompensationOptions o;
  o.points = 201;
  try {
    compensate_siemens(vmc(), o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("200"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mtcal
