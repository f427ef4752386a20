// ISG TF5280 target: volcomp.csv read back by the test's own reader of the ISG CSV format
// ('//' comments, '#' between blocks, a header of argument and parameter names), values against
// the model's parameters and motion functions; residual; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "mtcal/compensation/isg.hpp"
#include "mtcal/io/compensation/isg.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

struct Block {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

std::vector<Block> read_isg_csv(const std::string& text) {
  std::vector<Block> blocks(1);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("//", 0) == 0 || line.empty()) continue;
    if (line == "#") {
      blocks.emplace_back();
      continue;
    }
    std::istringstream ls(line);
    if (blocks.back().header.empty()) {
      for (std::string w; ls >> w;) blocks.back().header.push_back(w);
    } else {
      std::vector<double> row;
      for (double v; ls >> v;) row.push_back(v);
      EXPECT_EQ(row.size(), blocks.back().header.size()) << line;
      blocks.back().rows.push_back(row);
    }
  }
  return blocks;
}

TEST(IsgTarget, FileHoldsTheModelParametersAndMotionFunctions) {
  const Machine m = example("hu40t-wCBXfYZt.yaml");
  CompensationOptions o;
  o.points = 9;
  o.residual_points = 3;
  const auto blocks = read_isg_csv(isg_output(compensate_isg(m, o)).files.at(0).text);
  ASSERT_GE(blocks.size(), 2u);
  // Position errors: mtcal's location parameters without the leading E, one row.
  const Block& pos = blocks[0];
  ASSERT_EQ(pos.rows.size(), 1u);
  for (std::size_t k = 0; k < pos.header.size(); ++k) {
    const auto i = m.parameter_index("E" + pos.header[k]);
    ASSERT_TRUE(i) << pos.header[k];
    EXPECT_NEAR(pos.rows[0][k], m.parameter(*i), 1e-15);
  }
  // Component errors: the argument (mm or deg) then E<dir><axis> columns = the mean of both directions.
  std::size_t checked = 0;
  for (std::size_t b = 1; b < blocks.size(); ++b) {
    const Block& t = blocks[b];
    const Axis& ax = m.axis(t.header[0][0]);
    for (std::size_t k = 1; k < t.header.size(); ++k) {
      const auto name = ErrorName::parse(t.header[k]);
      ASSERT_TRUE(name && name->body == ax.letter) << t.header[k];
      const MotionFunction& f = ax.motion[static_cast<std::size_t>(index_of(name->component))];
      for (const auto& row : t.rows) {
        const double q = row[0] * joint_unit_factor(ax);
        EXPECT_NEAR(row[k], 0.5 * (f.value(q, 1) + f.value(q, -1)), 1e-12 * std::max(1.0, std::abs(row[k])));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100u);
}

TEST(IsgTarget, WithoutReversalAndSetUpOnlyInterpolationIsLeft) {
  Machine m = example("vmc-3axis.yaml");
  for (const char* p : {"EXX.b", "EZZ.b"}) m.set_parameter(p, 0.0);
  m.keep_only({"EXX", "EZZ", "EYX", "EZX", "EXY", "EC0Y", "EA0Z", "EB0Z"});  // polynomials and squareness
  CompensationOptions o;
  o.points = 201;
  const auto c = compensate_isg(m, o);
  EXPECT_TRUE(c.summary.not_compensated.empty());
  EXPECT_LT(c.summary.residual.max_norm_after, 0.01 * c.summary.residual.max_norm_before);
}

TEST(IsgTarget, BadInput) {
  Machine none = example("vmc-3axis.yaml");
  none.clear_errors();
  EXPECT_THROW(compensate_isg(none, {}), InputError);
}

}  // namespace
}  // namespace mtcal
