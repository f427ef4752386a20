// Etalon target and reader: the file read back by the test's own reader of the Etalon exchange format
// (TF5280 manual, "Etalon Exchange Format"), the control's rule (its parametric model with the tables
// interpolated) applied, the model's error recovered; mtcal's reader gives the parameters back; a
// file shaped as the manual's example; bad input with file, line and block.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "mtcal/compensation/isg.hpp"
#include "mtcal/io/compensation/etalon.hpp"
#include "mtcal/io/model/etalon_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

// The test's own reader: "[NAME]" blocks, "VALUE = v", "Gridpoints = {" rows "}" ; '//' comments.
struct TestBlocks {
  std::map<std::string, double> values;
  std::map<std::string, std::vector<std::pair<double, double>>> tables;
};
TestBlocks read_blocks(const std::string& text) {
  TestBlocks b;
  std::istringstream in(text);
  std::string line, name;
  bool grid = false;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find("//"));
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream ls(line);
    if (grid) {
      if (line.find('}') != std::string::npos) {
        grid = false;
        continue;
      }
      double a = 0, v = 0;
      EXPECT_TRUE(static_cast<bool>(ls >> a >> v)) << line;
      b.tables[name].push_back({a, v});
    } else if (line[0] == '[') {
      name = line.substr(1, line.find(']') - 1);
    } else if (line.rfind("VALUE = ", 0) == 0) {
      b.values[name] = std::stod(line.substr(8));
    } else {
      EXPECT_EQ(line.rfind("Gridpoints = {", 0), 0u) << line;
      grid = true;
    }
  }
  EXPECT_FALSE(grid);
  return b;
}

// A model the control's parametric model can hold: no reversal, no tool/workpiece set-up.
Machine holdable() {
  Machine m = example("vmc-3axis.yaml");
  for (const char* p : {"EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);
  m.keep_only({"EXX", "EZZ", "EYX", "EZX", "EXY", "EZY", "EAX", "EBY", "ECZ", "EC0Y", "EA0Z", "EB0Z"});
  return m;
}

TEST(EtalonTarget, ControlRuleRecoversTheModelErrorAtTheNodes) {
  const Machine m = holdable();
  CompensationOptions o;
  o.points = 11;
  o.residual_points = 3;
  const TargetOutput out = etalon_output(compensate_etalon(m, o));
  ASSERT_EQ(out.files.at(0).name, "volcomp.etalon");
  EXPECT_EQ(out.summary.target, "etalon");
  EXPECT_EQ(out.summary.quantity, TableQuantity::Error);
  const TestBlocks b = read_blocks(out.files.at(0).text);
  // The control's model: position errors as constants (named without E), component errors as
  // tables along their axis, linear interpolation (TF5280 manual, "Overview", "Etalon Exchange Format").
  Machine control = m;
  control.clear_errors();
  for (const auto& [name, v] : b.values) control.set_parameter("E" + name, v);
  for (const auto& [name, rows] : b.tables) {
    const auto n = ErrorName::parse(name);
    ASSERT_TRUE(n && n->kind == ErrorKind::Motion) << name;
    Table t;
    for (const auto& [a, v] : rows) {
      t.positions.push_back(a);  // linear axes: mm
      t.forward.push_back(v);
    }
    control.axes[*m.axis_index(n->body)].motion[static_cast<std::size_t>(index_of(n->component))] = MotionFunction(t);
  }
  EXPECT_EQ(b.values.size(), 3u);
  EXPECT_EQ(b.tables.size(), 9u);
  // At configurations made of table nodes the control's model must give the model's tool-point
  // error: the control moves the tool by minus it, so what is left is zero to 1e-9 mm.
  const ErrorModel model(m), cm(control);
  const std::vector<double> xs = {-400, -160, 0, 240, 400}, ys = {-250, -100, 0, 250}, zs = {-500, -250, 0};
  std::size_t checked = 0;
  for (double x : xs)
    for (double y : ys)
      for (double z : zs) {
        const std::vector<double> q = {x, y, z};
        const Vec3 e = model.evaluate(q).translation, ec = cm.evaluate(q).translation;
        EXPECT_LT((e - ec).norm(), 1e-9) << x << " " << y << " " << z;
        ++checked;
      }
  EXPECT_EQ(checked, 60u);
  EXPECT_LT(out.summary.residual.max_norm_after, 0.01 * out.summary.residual.max_norm_before);
}

TEST(EtalonReader, WriteThenReadGivesTheParametersBack) {
  const Machine m = example("hu40t-wCBXfYZt.yaml");
  CompensationOptions o;
  o.points = 13;
  o.residual_points = 2;
  const std::string text = etalon_text(compensate_etalon(m, o));
  ASSERT_TRUE(looks_like_etalon(text));
  Machine back = m;
  back.clear_errors();
  apply_etalon(back, text, "volcomp.etalon");
  // Position errors: the same doubles.
  std::size_t locations = 0;
  for (const auto& p : m.parameters())
    if (p.error.kind == ErrorKind::Location) {
      EXPECT_EQ(back.parameter(*back.parameter_index(p.name)), p.value) << p.name;
      locations += p.value != 0.0;
    }
  EXPECT_GT(locations, 5u);
  // Component errors: tables equal to the model's mean of both directions at every node.
  std::size_t nodes = 0;
  for (std::size_t a = 0; a < m.axes.size(); ++a)
    for (std::size_t c = 0; c < 6; ++c) {
      const MotionFunction& f = m.axes[a].motion[c];
      const MotionFunction& g = back.axes[a].motion[c];
      if (f.is_zero()) {
        EXPECT_TRUE(g.is_zero());
        continue;
      }
      const auto* t = std::get_if<Table>(&g.form());
      ASSERT_TRUE(t) << m.axes[a].letter << c;
      EXPECT_EQ(t->positions.size(), 13u);
      for (std::size_t i = 0; i < t->positions.size(); ++i) {
        const double q = t->positions[i];
        EXPECT_NEAR(t->forward[i], 0.5 * (f.value(q, 1) + f.value(q, -1)), 1e-15 + 1e-12 * std::abs(t->forward[i]));
        ++nodes;
      }
    }
  EXPECT_GT(nodes, 100u);
}

TEST(EtalonReader, ReadsAFileShapedAsTheManualExample) {
  // The shape of the TF5280 manual's example (vendor variant), values of our own.
  const std::string text =
      "// Every parameter is specified in a block.\n"
      "[C0B]\n"
      "VALUE = 0.000022355737\n"
      "[A0B]\n"
      "VALUE = 0.000047622950\n"
      "// Lookup tables are specified via a 2D array called \"Gridpoints\".\n"
      "[EXY]\n"
      "Gridpoints = {\n"
      "          -280.0 -0.001358635132\n"
      "          -270.0 -0.000240680764 // a comment after a row\n"
      "           270.0 -0.000316265101\n"
      "}  // end of EXY\n"
      "[ECC]\n"
      "gridpoints = {\n0 0.00001\n180 -0.00001\n360 0.00001 }\n";
  Machine m = example("hu40t-wCBXfYZt.yaml");
  m.clear_errors();
  apply_etalon(m, text, "example.etalon");
  EXPECT_EQ(m.parameter(*m.parameter_index("EC0B")), 0.000022355737);
  EXPECT_EQ(m.parameter(*m.parameter_index("EA0B")), 0.000047622950);
  const MotionFunction& exy = m.axis('Y').motion[0];
  EXPECT_NEAR(exy.value(-275.0, 1), 0.5 * (-0.001358635132 - 0.000240680764), 1e-15);
  EXPECT_NEAR(exy.value(0.0, -1), -0.000240680764 + (270.0 / 540.0) * (-0.000316265101 + 0.000240680764), 1e-15);
  // A rotary axis's arguments are degrees.
  const MotionFunction& ecc = m.axis('C').motion[5];
  EXPECT_NEAR(ecc.value(std::numbers::pi / 2, 1), 0.0, 1e-18);
  EXPECT_NEAR(ecc.value(std::numbers::pi, 1), -0.00001, 1e-18);
}

TEST(EtalonReader, ReadsWindowsLineEndingsAndAByteOrderMark) {
  const std::string text =
      "\xEF\xBB\xBF// exported\r\n[C0Y]\r\nVALUE = 2e-5\r\n[EXX]\r\nGridpoints = {\r\n-10 1e-3\r\n10 "
      "-1e-3\r\n}\r\n";
  ASSERT_TRUE(looks_like_etalon(text));
  Machine m = example("vmc-3axis.yaml");
  apply_etalon(m, text, "windows.etalon");
  EXPECT_EQ(m.parameter(*m.parameter_index("EC0Y")), 2e-5);
  EXPECT_NEAR(m.axis('X').motion[0].value(5.0, 1), -0.5e-3, 1e-15);
}

TEST(EtalonReader, IsAParameterFile) {
  const auto path = std::filesystem::temp_directory_path() / "mtcal_test_params.etalon";
  std::ofstream(path) << "// from a measurement\n[C0Y]\nVALUE = 1.5e-5\n";
  Machine m = example("vmc-3axis.yaml");
  load_parameters(m, path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(m.parameter(*m.parameter_index("EC0Y")), 1.5e-5);
  EXPECT_FALSE(looks_like_etalon("# yaml\nmtcal_parameters: 1\n"));
}

// Each bad input: one InputError naming the file, the line and the block.
void expect_refused(const std::string& text, int line, const std::string& field, const std::string& words) {
  Machine m = example("hu40t-wCBXfYZt.yaml");
  const Machine before = m;
  try {
    apply_etalon(m, text, "bad.etalon");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "bad.etalon") << text;
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().field, field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
  EXPECT_EQ(m.parameter(*m.parameter_index("EC0B")), before.parameter(*before.parameter_index("EC0B")));
}

TEST(EtalonReader, BadInput) {
  const std::string ok = "[C0B]\nVALUE = 1e-5\n";
  expect_refused(ok + "[GENERAL]\nVALUE = 1\n", 3, "GENERAL", "unknown position error [GENERAL]");
  expect_refused(ok + "[EXU]\nGridpoints = {\n0 0\n1 0\n}\n", 3, "EXU", "unknown component error");
  expect_refused(ok + "[Z0C]\nVALUE = 1\n", 3, "Z0C", "unknown position error");  // not a location of C
  expect_refused("[C0B]\nVALUE = 1e-5x\n", 2, "C0B", "expected a number after VALUE");
  expect_refused("[EXY]\nGridpoints = {\n0 0\n10 abc\n}\n", 4, "EXY row 2", "found 'abc'");
  expect_refused("[EXY]\nGridpoints = {\n0 0\n10 1 2\n}\n", 4, "EXY row 2", "found 3 word(s)");
  expect_refused("[EXY]\nGridpoints = {\n0 0\n10\n}\n", 4, "EXY row 2", "found 1 word(s)");
  expect_refused("[EXY]\nGridpoints = {\n10 0\n0 1\n}\n", 4, "EXY row 2", "strictly increasing");
  expect_refused("[EXY]\nGridpoints = {\n0 0\n10 1\n", 2, "EXY", "expected '}'");
  expect_refused("[EXY]\nGridpoints = {\n0 0\n}\n", 4, "EXY", "at least two");
  expect_refused("[C0B]\n[A0B]\nVALUE = 1\n", 1, "C0B", "found the next block");
  expect_refused(ok + "[C0B]\nVALUE = 2\n", 3, "C0B", "given twice");
  expect_refused("[C0B]\nVALUE = 1\nVALUE = 2\n", 3, "C0B", "second key");
  expect_refused("[C0B]\nOFFSET = 1\n", 2, "C0B", "found 'OFFSET'");
  expect_refused("VALUE = 1\n[C0B]\nVALUE = 1\n", 1, "", "block name in square brackets first");
  expect_refused("// nothing\n", 0, "", "found none");
  expect_refused(ok + "[C0B\n", 3, "", "square brackets");
  expect_refused("[C0B]\nVALUE = nan\n", 2, "C0B", "expected a number");
}

}  // namespace
}  // namespace mtcal
