// Sampled error tables against hand calculations from the example machine's polynomials.
#include <gtest/gtest.h>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::vmc;

// vmc-3axis.yaml: EXX = 0.5 + 8 q - 12 q^2 + 4 q^3 (um, q in m), reversal 1.0 um.
double exx_mm(double x_mm, int dir) {
  const double q = x_mm / 1000.0;
  return (0.5 + 8 * q - 12 * q * q + 4 * q * q * q + 1.0 * dir) / 1000.0;
}

TEST(CompensationTables, DefaultSamplingIsTheTravel) {
  const Machine m = vmc();
  const AxisSampling s = default_sampling(m, 'Z', 11);
  EXPECT_DOUBLE_EQ(s.start, -500.0);
  EXPECT_DOUBLE_EQ(s.end, 0.0);
  const auto p = sample_positions(s, "test");
  ASSERT_EQ(p.size(), 11u);
  EXPECT_DOUBLE_EQ(p[1], -450.0);
  EXPECT_EQ(p.back(), 0.0);
}

TEST(CompensationTables, BadSamplingNamesTheAxis) {
  EXPECT_THROW(sample_positions({'X', 0.0, 100.0, 1}, "test"), InputError);
  EXPECT_THROW(sample_positions({'X', 100.0, 100.0, 5}, "test"), InputError);
  EXPECT_THROW(sample_positions({'X', 0.0, std::nan(""), 5}, "test"), InputError);
  try {
    sample_positions({'Y', 10.0, -10.0, 5}, "plan.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "Y");
    EXPECT_NE(std::string(e.what()).find("plan.yaml"), std::string::npos);
  }
}

TEST(CompensationTables, ComponentIsTheMotionFunctionByHand) {
  const Machine m = vmc();
  const auto t = sample_component(m, Component::X, {'X', -400.0, 400.0, 9}, "test");
  EXPECT_EQ(t.error.str(), "EXX");
  for (std::size_t i = 0; i < t.position.size(); ++i) {
    EXPECT_NEAR(t.forward[i], exx_mm(t.position[i], +1), 1e-15) << t.position[i];
    EXPECT_NEAR(t.reverse[i], exx_mm(t.position[i], -1), 1e-15) << t.position[i];
  }
}

TEST(CompensationTables, JointErrorWithOnlyEXXIsEXXAlongX) {
  Machine m = vmc();
  m.keep_only({"EXX"});
  const ErrorModel model(m);
  const auto t = sample_joint_error(model, {'X', -400.0, 400.0, 5}, {}, "test");
  ASSERT_EQ(t.forward.size(), 5u);
  for (std::size_t i = 0; i < t.position.size(); ++i) {
    EXPECT_NEAR(t.forward[i].translation.x(), exx_mm(t.position[i], +1), 1e-12);
    EXPECT_NEAR(t.reverse[i].translation.x(), exx_mm(t.position[i], -1), 1e-12);
    EXPECT_NEAR(t.forward[i].translation.y(), 0.0, 1e-15);
    EXPECT_NEAR(t.forward[i].translation.z(), 0.0, 1e-15);
  }
  EXPECT_THROW(sample_joint_error(model, {'X', -400.0, 400.0, 5}, std::vector<double>{0.0}, "test"), InputError);
}

}  // namespace
}  // namespace mtcal
