// The exact model against the classic first-order 21-term sum model: they must agree to second
// order in the error size (difference shrinks 100x when the errors shrink 10x).
#include <gtest/gtest.h>

#include <cmath>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/kinematics/first_order.hpp"
#include "synthetic.hpp"

using namespace mtcal;

namespace {

// Largest |exact - first order| over configurations, for errors scaled by s.
double worst_difference(Machine m, double s, const std::vector<double>& q, const std::vector<std::int8_t>& dir) {
  const auto params = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i) m.set_parameter(i, params[i].value * s);
  const ErrorModel model(m);
  const std::size_t n = m.axes.size();
  double worst = 0;
  for (std::size_t r = 0; r < q.size() / n; ++r) {
    std::span<const double> qr(q.data() + r * n, n);
    std::span<const std::int8_t> dr(dir.data() + r * n, n);
    const auto e = model.evaluate(qr, dr);
    const auto f = first_order_error(m, qr, dr);
    worst = std::max({worst, (e.translation - f.translation).norm(), 1e3 * (e.rotation - f.rotation).norm()});
  }
  return worst;
}

void expect_second_order(const Machine& m) {
  std::vector<std::int8_t> dir;
  const auto q = mtcal::testing::random_configurations(m, 100, 3, &dir);
  const double d1 = worst_difference(m, 1.0, q, dir);
  const double d2 = worst_difference(m, 0.1, q, dir);
  const double d3 = worst_difference(m, 0.01, q, dir);
  EXPECT_GT(d1, 0.0);
  // Quadratic: each factor 10 in error size gives a factor 100 in the difference.
  EXPECT_NEAR(d1 / d2, 100.0, 10.0) << d1 << " " << d2;
  EXPECT_NEAR(d2 / d3, 100.0, 10.0) << d2 << " " << d3;
}

}  // namespace

TEST(FirstOrder, ExactModelAgreesToSecondOrderOnTheExample) {
  Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  // Add mounting errors too so that every term of the sum model is exercised.
  m.set_parameter("EXt", 2e-3);
  m.set_parameter("EBt", 3e-5);
  m.set_parameter("EAw", -4e-5);
  m.set_parameter("EYw", 1e-3);
  // Scale up so the second-order part stands well above rounding at the smallest scale.
  const auto params = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i) m.set_parameter(i, params[i].value * 50.0);
  expect_second_order(m);
}

TEST(FirstOrder, ExactModelAgreesToSecondOrderForEveryThreeAxisTopology) {
  for (const char* topo : {"wXYfZt", "wfXYZt", "wYXfZt", "wXfYZt", "wZfXYt", "wXYZft"}) {
    for (bool reversed : {false, true}) {
      SCOPED_TRACE(std::string(topo) + (reversed ? " reversed" : ""));
      Machine m = mtcal::testing::nominal_machine(topo, reversed);
      mtcal::testing::randomize_errors(m, 77, 50.0);
      expect_second_order(m);
    }
  }
}

TEST(FirstOrder, HandCalculationOfFletcherStyleTerms) {
  // wfXYZt (all axes move the tool, Fletcher's wBMTt): X error at (x, y, z) with tool length L:
  // EXX + (yaw of X) * (-y) + (pitch of X) * (z - L) + ... here only three terms, first order.
  Machine m = mtcal::testing::nominal_machine("wfXYZt");
  m.tool.length = 100;
  m.tool.spindle_point = Vec3::Zero();
  for (auto& ax : m.axes) ax.point = Vec3::Zero();
  m.set_parameter("EXX.1", 1e-5);
  m.set_parameter("ECX.0", 2e-5);
  m.set_parameter("EBX.0", 3e-5);
  const std::vector<double> q{200, 150, -300};
  const auto f = first_order_error(m, q);
  // dx = 1e-5 * 200 - 2e-5 * 150 + 3e-5 * (-300 - 100)
  EXPECT_NEAR(f.translation.x(), 2e-3 - 3e-3 - 12e-3, 1e-15);
  // The exact model differs by second-order terms only: beta^2 * 400 / 2 ~ 2e-7 mm.
  EXPECT_NEAR(ErrorModel(m).evaluate(q).translation.x(), f.translation.x(), 1e-6);
}

TEST(FirstOrder, RejectsRotaryAxes) {
  const Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  EXPECT_THROW(first_order_error(m, std::vector<double>(5, 0.0)), ModelError);
}
