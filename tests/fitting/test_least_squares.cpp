// analyse_jacobian against a hand-computed 3x2 case and a rank-deficient one.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Core>

#include "mtcal/fitting/least_squares.hpp"

using namespace mtcal;

// J = [1 0; 0 1; 1 1]: J^T J = [2 1; 1 2], (J^T J)^-1 = [2 -1; -1 2] / 3, eigenvalues 3 and 1.
TEST(AnalyseJacobian, HandComputed3x2) {
  Eigen::MatrixXd J(3, 2);
  J << 1, 0, 0, 1, 1, 1;
  for (bool scaled : {false, true}) {
    const JacobianAnalysis a = analyse_jacobian(J, 1.5, JacobianOptions{1e-10, scaled});
    EXPECT_EQ(a.rank, 2u);
    EXPECT_TRUE(a.full_rank());
    ASSERT_EQ(a.singular_values.size(), 2);
    // Scaled: both columns have norm sqrt(2), so the singular values are divided by it.
    const double f = scaled ? 1 / std::sqrt(2.0) : 1.0;
    EXPECT_NEAR(a.singular_values[0], std::sqrt(3.0) * f, 1e-15);
    EXPECT_NEAR(a.singular_values[1], 1.0 * f, 1e-15);
    EXPECT_NEAR(a.condition, std::sqrt(3.0), 1e-14);
    // 1.5 * [2 -1; -1 2] / 3 = [1 -0.5; -0.5 1].
    EXPECT_NEAR(a.covariance(0, 0), 1.0, 1e-15);
    EXPECT_NEAR(a.covariance(1, 1), 1.0, 1e-15);
    EXPECT_NEAR(a.covariance(0, 1), -0.5, 1e-15);
    EXPECT_NEAR(a.covariance(1, 0), -0.5, 1e-15);
    EXPECT_NEAR(a.uncertainty[0], 1.0, 1e-15);
    EXPECT_NEAR(a.uncertainty[1], 1.0, 1e-15);
    EXPECT_EQ(a.correlation(0, 0), 1.0);
    EXPECT_NEAR(a.correlation(0, 1), -0.5, 1e-15);
  }
}

// Column scaling makes rank and condition independent of the units of the unknowns.
TEST(AnalyseJacobian, ScalingRemovesUnits) {
  Eigen::MatrixXd J(3, 2);
  J << 1, 0, 0, 1e-6, 1, 1e-6;  // second unknown in units a million times larger
  const auto scaled = analyse_jacobian(J, 1.0);
  EXPECT_NEAR(scaled.condition, std::sqrt(3.0), 1e-12);
  const auto raw = analyse_jacobian(J, 1.0, JacobianOptions{1e-10, false});
  EXPECT_GT(raw.condition, 1e5);
  // The covariance does not depend on the scaling: var of the second unknown is 2/3 * 1e12.
  EXPECT_NEAR(scaled.covariance(1, 1) / (2.0 / 3.0 * 1e12), 1.0, 1e-12);
  EXPECT_NEAR(raw.covariance(1, 1) / scaled.covariance(1, 1), 1.0, 1e-9);
}

TEST(AnalyseJacobian, RankDeficientGivesNaN) {
  Eigen::MatrixXd J(3, 2);
  J << 1, 2, 2, 4, 3, 6;  // second column twice the first
  const JacobianAnalysis a = analyse_jacobian(J, 1.0);
  EXPECT_EQ(a.rank, 1u);
  EXPECT_FALSE(a.full_rank());
  EXPECT_TRUE(std::isinf(a.condition));
  EXPECT_NEAR(a.singular_values[0], std::sqrt(2.0), 1e-14);  // two equal unit columns
  for (Eigen::Index i = 0; i < 2; ++i) {
    EXPECT_TRUE(std::isnan(a.uncertainty[i]));
    for (Eigen::Index j = 0; j < 2; ++j) {
      EXPECT_TRUE(std::isnan(a.covariance(i, j)));
      EXPECT_TRUE(std::isnan(a.correlation(i, j)));
    }
  }
  Eigen::MatrixXd Z(3, 2);
  Z << 1, 0, 2, 0, 3, 0;  // a zero column: the unknown is not determined at all
  EXPECT_EQ(analyse_jacobian(Z, 1.0).rank, 1u);
  Eigen::MatrixXd wide(1, 2);
  wide << 1, 1;  // fewer rows than unknowns
  const auto w = analyse_jacobian(wide, 1.0);
  EXPECT_EQ(w.rank, 1u);
  EXPECT_FALSE(w.full_rank());
}
