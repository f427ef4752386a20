// HEIDENHAIN target: the *.COM and *.CMA tables read back by the test's own reader of the TNC table
// syntax (BEGIN line, header of fixed-width columns, rows, [END]), the documented rule applied
// ([axis of the *.COM column] = F(axis of the *.CMA column), the control moving each axis by minus
// the value: an assumption), the model's error recovered at the nodes; residual; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "mtcal/compensation/heidenhain.hpp"
#include "mtcal/io/compensation/heidenhain.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

const TargetFile& heidenhain_file_named(const TargetOutput& out, const std::string& name) {
  for (const auto& f : out.files)
    if (f.name == name) return f;
  throw std::runtime_error("no file " + name);
}

// The test's reader of a TNC table: column name -> cells (text), checking the BEGIN/[END] lines and
// that every cell starts at its header's column.
std::map<std::string, std::vector<std::string>> read_tnc_table(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("BEGIN " + name, 0), 0u) << line;
  std::getline(in, line);
  std::vector<std::pair<std::string, std::size_t>> columns;  // name, start
  for (std::size_t i = 0; i < line.size();) {
    if (line[i] == ' ') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ') ++i;
    columns.push_back({line.substr(start, i - start), start});
  }
  std::map<std::string, std::vector<std::string>> cells;
  bool end = false;
  while (std::getline(in, line)) {
    if (line == "[END]") {
      end = true;
      continue;
    }
    EXPECT_FALSE(end) << "text after [END]: " << line;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const std::size_t start = columns[c].second;
      EXPECT_NE(line.size() > start ? line[start] : ' ', ' ')
          << "cell not at column " << columns[c].first << ": " << line;
      EXPECT_TRUE(start == 0 || line[start - 1] == ' ') << line;
      std::istringstream cell(line.substr(start));
      std::string word;
      cell >> word;
      cells[columns[c].first].push_back(word);
    }
  }
  EXPECT_TRUE(end) << name;
  return cells;
}

std::vector<double> numbers(const std::vector<std::string>& cells) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(std::stod(c));
  return v;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double q) {
  if (q <= x.front()) return y.front();
  if (q >= x.back()) return y.back();
  std::size_t i = 1;
  while (x[i] < q) ++i;
  return y[i - 1] + (q - x[i - 1]) / (x[i] - x[i - 1]) * (y[i] - y[i - 1]);
}

TEST(HeidenhainTarget, TablesRecoverTheModelErrorAlongEachAxisLine) {
  const Machine m = example("vmc-3axis.yaml");
  CompensationOptions o;
  o.points = 21;
  o.residual_points = 3;
  const TargetOutput out = heidenhain_output(compensate_heidenhain(m, o));
  EXPECT_EQ(out.summary.quantity, TableQuantity::Error);
  EXPECT_NE(out.summary.sign_source.find("must be checked on the control"), std::string::npos);
  // config.cma: the active line assigns each table to its argument axis.
  const auto cma = read_tnc_table(heidenhain_file_named(out, "config.cma").text, "config.cma");
  EXPECT_EQ(cma.at("ACTIVE").at(0), "*");
  // The control's rule: axis K gets -sum over the tables T(L) of column K interpolated at q_L.
  std::map<char, std::map<std::string, std::vector<std::string>>> tables;
  for (const char l : std::string("XYZ")) {
    const std::string name = cma.at(std::string(1, l)).at(0);
    EXPECT_EQ(name, std::string(1, l) + ".COM");
    tables[l] = read_tnc_table(heidenhain_file_named(out, name).text, name);
    EXPECT_NE(heidenhain_file_named(out, name).text.find("MM\n"), std::string::npos);
  }
  auto correction = [&](const std::vector<double>& q, char k) {
    double c = 0.0;
    for (const char l : std::string("XYZ")) {
      const auto& t = tables[l];
      if (!t.count(std::string(1, k))) continue;
      c -=
          interpolate(numbers(t.at("AXISPOS")), numbers(t.at(std::string(1, k))), q[static_cast<std::size_t>(l - 'X')]);
    }
    return c;
  };
  // Along each axis line through the reference (0, 0, 0), at the nodes: the correction is minus
  // the model's error (mean of both directions) along every axis, to 1e-9 mm.
  const ErrorModel model(m);
  std::size_t checked = 0;
  for (const char l : std::string("XYZ")) {
    const auto pos = numbers(tables[l].at("AXISPOS"));
    EXPECT_EQ(pos.size(), 21u);
    for (const double p : pos) {
      std::vector<double> q(3, 0.0);
      q[static_cast<std::size_t>(l - 'X')] = p;
      const std::vector<std::int8_t> plus(3, 1), minus(3, -1);
      const Vec3 e = 0.5 * (model.evaluate(q, plus).translation + model.evaluate(q, minus).translation);
      for (const char k : std::string("XYZ")) {
        EXPECT_NEAR(correction(q, k), -e[k - 'X'], 1e-9) << l << "=" << p << " axis " << k;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 189u);
  // Straightness columns exist: Y = F(X) from EYX, Z = F(X) from EZX.
  EXPECT_TRUE(tables['X'].count("Y") && tables['X'].count("Z"));
}

TEST(HeidenhainTarget, PositioningAndStraightnessLeaveOnlyInterpolation) {
  Machine m = example("vmc-3axis.yaml");
  for (const char* p : {"EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);
  m.keep_only({"EXX", "EZZ", "EYX", "EZX", "EXY", "EZY", "EXZ", "EYZ"});
  CompensationOptions o;
  o.points = 201;
  o.residual_points = 7;
  const auto c = compensate_heidenhain(m, o);
  EXPECT_TRUE(c.summary.not_compensated.empty());
  EXPECT_GT(c.summary.residual.max_norm_before, 0.005);
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
}

TEST(HeidenhainTarget, ListsWhatItCannotHold) {
  const Machine m = example("hu40t-wCBXfYZt.yaml");
  CompensationOptions o;
  o.points = 11;
  o.residual_points = 3;
  const auto c = compensate_heidenhain(m, o);
  std::string listed;
  for (const auto& n : c.summary.not_compensated) listed += n.what + ";";
  for (const char* e : {"EC0Y", "ECC", "reversal"}) EXPECT_NE(listed.find(e), std::string::npos) << e << ": " << listed;
  EXPECT_LT(c.summary.residual.max_norm_after, c.summary.residual.max_norm_before);
  // The library speaks of the data (the reference position), not of a command's option.
  for (const auto& w : c.summary.warnings) EXPECT_EQ(w.find("--"), std::string::npos) << w;
}

TEST(HeidenhainTarget, BadInput) {
  Machine none = example("vmc-3axis.yaml");
  none.keep_only({"EAX"});  // an angle alone, at the reference position with no offset: nothing along an axis
  none.set_parameter("EAX.1", 0.0);
  EXPECT_THROW(compensate_heidenhain(none, {}), InputError);
  CompensationOptions o;
  o.points = 257;
  EXPECT_THROW(compensate_heidenhain(example("vmc-3axis.yaml"), o), InputError);
}

}  // namespace
}  // namespace mtcal
