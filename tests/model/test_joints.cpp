// Joint values and grids as users write them on the command line (mm and deg).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mtcal/io/text/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

using namespace mtcal;

TEST(Joints, ParsesValuesInUserUnitsAndDefaultsToZero) {
  const Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  const auto q = parse_joint_values(m, "X=100,B=30,Z=-2.5", "test");
  ASSERT_EQ(q.size(), 5u);
  EXPECT_EQ(q[0], 0.0);                                 // C not named
  EXPECT_DOUBLE_EQ(q[1], 30 * std::numbers::pi / 180);  // B in deg
  EXPECT_EQ(q[2], 100.0);
  EXPECT_EQ(q[4], -2.5);
  EXPECT_EQ(to_user_units(m.axes[1], q[1]), 30.0);
}

TEST(Joints, GridsSpanTheirRangeInclusive) {
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");
  const auto g = parse_grid(m, "X=-100:100:5,Z=7", "test grid");
  EXPECT_EQ(g[0], (std::vector<double>{-100, -50, 0, 50, 100}));
  EXPECT_EQ(g[1], (std::vector<double>{0}));
  EXPECT_EQ(g[2], (std::vector<double>{7}));
  EXPECT_EQ(parse_grid(m, "Y=3:9:1", "test grid")[1], (std::vector<double>{3}));
}

TEST(Joints, RejectsBadSpecifications) {
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");
  for (const char* s : {"", "X", "X=", "=1", "Q=1", "X=1,X=2", "X=abc", "XY=1", "X=1,,Y=2"})
    EXPECT_THROW(parse_joint_values(m, s, "test"), InputError) << s;
  for (const char* s : {"X=1:2", "X=1:2:0", "X=1:2:2.5", "X=1:2:-3", "X=a:2:3", "X=1:2:3:4", "X=1:2:1e9"})
    EXPECT_THROW(parse_grid(m, s, "test grid"), InputError) << s;
  // Extreme ends do not overflow into NaN, and the last value is exactly the upper end.
  const auto g = parse_grid(m, "X=-1e308:1e308:3", "test grid")[0];
  EXPECT_EQ(g, (std::vector<double>{-1e308, 0.0, 1e308}));
  EXPECT_EQ(parse_grid(m, "X=0.1:0.7:7", "test grid")[0].back(), 0.7);
}

TEST(Joints, TravelCheckNamesTheAxisAndItsLimits) {
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");  // travels [-400, 400]
  EXPECT_NO_THROW(check_joints(m, {400, -400, 0}, "--at", true));
  EXPECT_NO_THROW(check_joints(m, {0, 401, 0}, "--at", false));
  EXPECT_THROW(check_joints(m, {std::nan(""), 0, 0}, "--at", false), InputError);
  EXPECT_THROW(check_joints(m, {std::nan(""), 0, 0}, "--at", true), InputError);
  EXPECT_THROW(check_joints(m, {0, 2e6, 0}, "--at", false), InputError);
  try {
    check_joints(m, {0, 401, 0}, "--at", true);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "Y");
    EXPECT_NE(std::string(e.what()).find("[-400, 400]"), std::string::npos) << e.what();
  }
}
