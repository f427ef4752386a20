// Contributions of single errors: hand cases, sum against the exact model, second-order residual.
#include <gtest/gtest.h>

#include <cmath>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::vmc;

namespace mt = ::mtcal::testing;

TEST(Contributions, SquarenessHandCalculation) {
  // Only EC0Y (squareness of Y to X, rad): a Y move of y shifts the tool along X by -EC0Y * y or
  // +EC0Y * y depending on the sign convention; its magnitude is |EC0Y| * |dy| exactly at first order,
  // and for a pair differing only in Y the whole difference comes from EC0Y.
  Machine m = vmc();
  m.clear_errors();
  m.set_parameter("EC0Y", 20e-6);
  const auto a = parse_joint_values(m, "X=0,Y=200,Z=-100", "test");
  const auto b = parse_joint_values(m, "X=0,Y=-200,Z=-100", "test");
  const auto r = contributions(m, a, {}, std::span<const double>(b));
  ASSERT_EQ(r.items.size(), 1u);
  EXPECT_EQ(r.items[0].error.str(), "EC0Y");
  // EC0Y > 0 tilts Y towards -X (docs/conventions.md: dx = -Y sin(EC0Y)): from Y=-200 to Y=200, -8 um.
  EXPECT_NEAR(r.items[0].effect.x(), -20e-6 * 400, 1e-12);
  EXPECT_NEAR(r.items[0].effect.y(), 0.0, 1e-15);
  EXPECT_NEAR(r.items[0].share, 1.0, 1e-9);
  EXPECT_NEAR(r.items[0].along, r.exact.norm(), 1e-9);
  // What is left is second order: the exact rotation shortens Y by (1 - cos c) y = c^2 / 2 * 200 mm
  // at each end, in opposite senses: c^2 * 200 mm in all.
  EXPECT_NEAR(r.residual, 20e-6 * 20e-6 * 200, 1e-12);
}

TEST(Contributions, LinearPositioningErrorAtAPoint) {
  // Only EXX = 10 um/m * x (EXX.1 = 1e-5): at X = 300 the error is 3 um along X, all of it EXX.
  Machine m = vmc();
  m.clear_errors();
  m.set_parameter("EXX.1", 1e-5);
  const auto q = parse_joint_values(m, "X=300", "test");
  const auto r = contributions(m, q);
  ASSERT_EQ(r.items.size(), 1u);
  EXPECT_EQ(r.items[0].error.str(), "EXX");
  EXPECT_NEAR(r.items[0].effect.x(), 0.003, 1e-15);
  EXPECT_NEAR(r.exact.x(), 0.003, 1e-13);  // the exact chain's rounding
  EXPECT_NEAR(error_value(m, r.items[0].error, q), 0.003, 1e-15);
}

TEST(Contributions, SumMatchesExactToSecondOrder) {
  // Over topologies and random errors: the residual |exact - sum| shrinks 100x when every error
  // shrinks 10x (second order), and is far below |exact| at realistic sizes.
  for (const char* topo : {"wXfYZt", "wYfXZt", "wCBXfYZt", "wXYfZACt"}) {
    Machine m = mt::nominal_machine(topo);
    mt::randomize_errors(m, 11);
    const auto q = mt::random_configurations(m, 2, 5);
    const std::span<const double> a(q.data(), m.axes.size()), b(q.data() + m.axes.size(), m.axes.size());
    const auto r1 = contributions(m, a, {}, b);
    EXPECT_LT(r1.residual, 1e-2 * r1.exact.norm()) << topo;
    double share = 0;
    for (const auto& c : r1.items) share += c.share;
    EXPECT_NEAR(share, 1.0, 1e-2) << topo;
    Machine small = mt::nominal_machine(topo);
    mt::randomize_errors(small, 11, 0.1);
    const auto r2 = contributions(small, a, {}, b);
    EXPECT_NEAR(r2.exact.norm() / r1.exact.norm(), 0.1, 0.01) << topo;
    EXPECT_NEAR(r1.residual / r2.residual, 100.0, 10.0) << topo;
    // Sorted by the size of their part along the difference.
    for (std::size_t k = 1; k < r1.items.size(); ++k)
      EXPECT_GE(std::abs(r1.items[k - 1].along), std::abs(r1.items[k].along));
  }
}

TEST(Contributions, ReversalTermsFollowTheDirections) {
  // EXX.b = 5 um: moving +X adds +5 um, moving -X adds -5 um; the pair (dir -1 -> dir +1) differs by 10 um.
  Machine m = vmc();
  m.clear_errors();
  m.set_parameter("EXX.b", 0.005);
  const auto q = parse_joint_values(m, "X=100", "test");
  const std::vector<std::int8_t> up{1, 0, 0}, down{-1, 0, 0};
  const auto r = contributions(m, q, up, std::span<const double>(q), down);
  ASSERT_EQ(r.items.size(), 1u);
  EXPECT_NEAR(r.items[0].effect.x(), 0.010, 1e-12);
  EXPECT_NEAR(r.exact.x(), 0.010, 1e-12);
  EXPECT_TRUE(contributions(m, q).items.empty());  // no direction: no reversal term
}

TEST(Contributions, RemovingAnErrorRemovesItsContribution) {
  Machine m = vmc();
  const auto q = parse_joint_values(m, "X=250,Y=-100,Z=-400", "test");
  const auto r = contributions(m, q);
  ASSERT_FALSE(r.items.empty());
  const ErrorName top = r.items[0].error;
  const Machine without = without_error(m, top);
  for (const auto& e : nonzero_errors(without)) EXPECT_FALSE(e == top);
  const auto r2 = contributions(without, q);
  // First order is linear: the sum drops by exactly the removed effect.
  EXPECT_LT((r.first_order - r.items[0].effect - r2.first_order).norm(), 1e-15);
  EXPECT_EQ(nonzero_errors(m).size(), nonzero_errors(without).size() + 1);
}

}  // namespace
}  // namespace mtcal
