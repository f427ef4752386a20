// The analytic sensitivity Jacobian against central differences, for every parameter of every
// example machine and of synthetic machines of many topologies, at zero, tiny and random errors.
#include <gtest/gtest.h>

#include "jacobian_check.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

using namespace mtcal;

namespace {

void check(const Machine& m, std::size_t configurations, std::uint64_t seed) {
  std::vector<std::int8_t> dir;
  const auto q = mtcal::testing::random_configurations(m, configurations, seed, &dir);
  const std::size_t n = m.axes.size();
  const ErrorModel model(m);
  JacobianWorkspace ws;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, static_cast<Eigen::Index>(m.parameter_count()));
  const auto params = m.parameters();
  for (std::size_t r = 0; r < configurations; ++r) {
    std::span<const double> qr(q.data() + r * n, n);
    std::span<const std::int8_t> dr(dir.data() + r * n, n);
    model.jacobian(qr, dr, J, ws);
    const auto N = mtcal::testing::numeric_jacobian(m, qr, dr);
    for (Eigen::Index c = 0; c < J.cols(); ++c) {
      const double scale = std::max(N.col(c).norm(), J.col(c).norm());
      EXPECT_LE((J.col(c) - N.col(c)).norm(), 1e-6 * scale + 1e-12)
          << m.name << " parameter " << params[static_cast<std::size_t>(c)].name << " config " << r << "\nanalytic "
          << J.col(c).transpose() << "\nnumeric  " << N.col(c).transpose();
    }
  }
}

}  // namespace

TEST(Jacobian, MatchesCentralDifferencesForEveryExample) {
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"}) {
    SCOPED_TRACE(f);
    check(load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + f), 3, 17);
  }
}

TEST(Jacobian, MatchesCentralDifferencesAtZeroTinyAndRandomErrors) {
  for (const char* topo : {"wXYfZt", "wCBXfYZt", "wCAYXfZt", "wXfYZCAt", "wfXYZBCt", "wBfXYZCt"}) {
    SCOPED_TRACE(topo);
    Machine m = mtcal::testing::nominal_machine(topo);
    check(m, 2, 1);  // zero errors
    mtcal::testing::randomize_errors(m, 5, 1e-6);
    check(m, 2, 2);  // tiny errors
    mtcal::testing::randomize_errors(m, 6, 1.0);
    check(m, 2, 3);  // realistic errors
    mtcal::testing::randomize_errors(m, 7, 2000.0);
    check(m, 2, 4);  // large errors: the exact transforms' non-linearity shows
  }
}

TEST(Jacobian, MatchesCentralDifferencesOnReversedAxes) {
  for (const char* topo : {"wXYfZt", "wCBXfYZt", "wXfYZCAt"}) {
    SCOPED_TRACE(topo);
    Machine m = mtcal::testing::nominal_machine(topo, true);
    mtcal::testing::randomize_errors(m, 9, 1.0);
    check(m, 2, 5);
  }
}

TEST(Jacobian, PredictsTheChangeOfErrorToFirstOrder) {
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, 31);
  const std::vector<double> q{0.7, -0.4, 120.0, -80.0, 45.0};
  const ErrorModel model(m);
  const auto J = model.jacobian(q);
  Machine moved = m;
  Eigen::VectorXd dp(J.cols());
  Machine step = m;
  mtcal::testing::randomize_errors(step, 32, 1e-3);
  for (Eigen::Index i = 0; i < J.cols(); ++i) {
    dp[i] = step.parameter(static_cast<std::size_t>(i));
    moved.set_parameter(static_cast<std::size_t>(i), m.parameter(static_cast<std::size_t>(i)) + dp[i]);
  }
  const auto a = model.evaluate(q), b = ErrorModel(moved).evaluate(q);
  Eigen::Matrix<double, 6, 1> d;
  d << b.translation - a.translation, b.rotation - a.rotation;
  const Eigen::Matrix<double, 6, 1> predicted = J * dp;
  EXPECT_LE((d - predicted).norm(), 1e-6 * d.norm());
}

TEST(Jacobian, RejectsWrongColumnCount) {
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, 3);
  JacobianWorkspace ws;
  EXPECT_THROW(ErrorModel(m).jacobian(std::vector<double>{0, 0, 0}, {}, J, ws), ModelError);
}
