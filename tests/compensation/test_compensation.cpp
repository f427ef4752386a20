// Table interpolation and the residual prediction, against hand values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

TEST(InterpolateHeld, LinearInsideHeldOutside) {
  const std::vector<double> p{0.0, 10.0, 30.0}, v{1.0, 3.0, -1.0};
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, -5.0), 1.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 5.0), 2.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 10.0), 3.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 20.0), 1.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 30.0), -1.0);
  EXPECT_DOUBLE_EQ(interpolate_held(p, v, 1e9), -1.0);
  const std::vector<double> one{2.0}, w{7.0};
  EXPECT_DOUBLE_EQ(interpolate_held(one, w, -3.0), 7.0);
  EXPECT_THROW(interpolate_held(p, w, 0.0), ModelError);
}

// A controller's table and its rule, against hand values: interpolation and held ends, the column
// of the direction of motion, the sign, the table's unit and a rotary axis's turn.
TEST(ControllerTable, AppliesItsRuleAsTheControllerDoes) {
  ControllerTable t{.input = 1, .output = 0, .position = {0.0, 10.0, 30.0}, .forward = {1.0, 3.0, -1.0},
                    .reverse = {2.0, 4.0, 0.0}, .sign = -1.0};
  EXPECT_DOUBLE_EQ(t.value_at(5.0, +1), -2.0);   // -(1 + 3) / 2
  EXPECT_DOUBLE_EQ(t.value_at(5.0, 0), -2.0);    // not moving: the forward column, as LinuxCNC's comp
  EXPECT_DOUBLE_EQ(t.value_at(5.0, -1), -3.0);   // -(2 + 4) / 2
  EXPECT_DOUBLE_EQ(t.value_at(-1e9, -1), -2.0);  // held below the first node
  EXPECT_DOUBLE_EQ(t.value_at(99.0, +1), 1.0);   // held above the last
  t.reverse.clear();                             // one column for both directions
  EXPECT_DOUBLE_EQ(t.value_at(5.0, -1), -2.0);
  // A rotary axis in deg, table over one turn (FANUC): 370 deg reads the table at 10 deg, 355 deg
  // at 355 deg; positions and values in deg, q and the result in rad.
  const double deg = std::acos(-1.0) / 180.0;
  ControllerTable turn{.position = {0.0, 180.0, 360.0}, .forward = {0.0, 0.018, 0.0}, .unit = deg, .wrap_turn = true};
  EXPECT_NEAR(turn.value_at(370.0 * deg, +1), 0.001 * deg, 1e-15);
  EXPECT_NEAR(turn.value_at(-5.0 * deg, +1), 0.0005 * deg, 1e-15);
  // The rule: tables on one joint are summed, on the joint the table names, by the input's direction.
  const auto rule = table_rule({t, ControllerTable{.input = 0, .output = 0, .position = {0.0}, .forward = {0.25}}}, 2);
  const std::vector<double> q{7.0, 5.0};
  const std::vector<std::int8_t> dir{-1, +1};
  const AppliedCorrection c = rule(q, dir);
  ASSERT_EQ(c.joint.size(), 2u);
  EXPECT_DOUBLE_EQ(c.joint[0], -2.0 + 0.25);
  EXPECT_DOUBLE_EQ(c.joint[1], 0.0);
  EXPECT_THROW(table_rule({ControllerTable{.input = 2, .output = 0, .position = {0.0}, .forward = {1.0}}}, 2), ModelError);
}

TEST(PredictResidual, NoCorrectionLeavesTheErrorAndExactCorrectionRemovesIt) {
  Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  m.keep_only({"EXX"});
  const ErrorModel model(m);
  std::vector<std::vector<double>> grid{{-400.0, -100.0, 0.0, 250.0, 400.0}, {0.0, 100.0}, {-300.0}};
  // EXX = 0.5 + 8 q - 12 q^2 + 4 q^3 +- 1.0 um (q in m): -5.876 um at X = -400 in reverse,
  // +3.036 um at X = 400 forward.
  auto exx = [](double x_mm, int dir) {
    const double q = x_mm / 1000.0;
    return (0.5 + 8 * q - 12 * q * q + 4 * q * q * q + dir) / 1000.0;
  };
  const auto none = predict_residual(
      model, grid, [](auto, auto) { return AppliedCorrection{}; }, 1);
  EXPECT_EQ(none.configurations, 10u);
  EXPECT_NEAR(none.max_before[0], -exx(-400.0, -1), 1e-12);
  EXPECT_NEAR(none.max_before[0], 5.876e-3, 1e-12);
  EXPECT_NEAR(none.max_after[0], none.max_before[0], 1e-15);
  EXPECT_NEAR(none.max_before[1], 0.0, 1e-15);
  // VA: largest difference of two x errors, X = 400 forward against X = -400 reverse.
  EXPECT_NEAR(none.va_before, exx(400.0, 1) - exx(-400.0, -1), 1e-12);

  const auto exact = predict_residual(
      model, grid,
      [&](std::span<const double> q, std::span<const std::int8_t> dir) {
        AppliedCorrection c;
        c.joint = {-exx(q[0], dir[0]), 0.0, 0.0};
        return c;
      },
      2);
  // Left: EXX's slope times the correction, at X = -400: 19.52 um/m * 5.876 um = 1.147e-7 mm.
  EXPECT_NEAR(exact.max_after[0], 19.52e-6 * 5.876e-3, 2e-9);
  EXPECT_LT(exact.va_after, 2.5e-7);
  EXPECT_NEAR(exact.max_before[0], none.max_before[0], 1e-15);

  const auto cartesian = predict_residual(
      model, grid,
      [&](std::span<const double> q, std::span<const std::int8_t> dir) {
        AppliedCorrection c;
        c.cartesian = Vec3(-exx(q[0], dir[0]), 0.0, 0.0);
        return c;
      },
      1);
  EXPECT_LT(cartesian.max_after[0], 1e-14);  // rounding of the chain only
}

}  // namespace
}  // namespace mtcal
