#include "mtcal/fitting/least_squares.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace mtcal {

JacobianAnalysis analyse_jacobian(const Eigen::MatrixXd& J, double sigma0_squared, const JacobianOptions& options) {
  const Eigen::Index p = J.cols();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(p);
  Eigen::MatrixXd S = J;
  if (options.scale_columns)
    for (Eigen::Index j = 0; j < p; ++j) {
      const double norm = J.col(j).norm();
      if (norm > 0.0) {
        S.col(j) /= norm;
        scale[j] = 1.0 / norm;
      }
    }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(S, Eigen::ComputeThinV);
  JacobianAnalysis a;
  a.columns = static_cast<std::size_t>(p);
  a.singular_values = svd.singularValues();
  const double smax = p > 0 && a.singular_values.size() > 0 ? a.singular_values[0] : 0.0;
  for (Eigen::Index i = 0; i < a.singular_values.size(); ++i)
    a.rank += a.singular_values[i] > options.relative_tolerance * smax ? 1 : 0;
  const auto k = static_cast<std::size_t>(a.singular_values.size());
  a.condition = a.rank == k && k > 0 ? smax / a.singular_values[a.singular_values.size() - 1]
                                     : std::numeric_limits<double>::infinity();
  a.covariance = Eigen::MatrixXd::Constant(p, p, nan);
  a.uncertainty = Eigen::VectorXd::Constant(p, nan);
  a.correlation = Eigen::MatrixXd::Constant(p, p, nan);
  if (!a.full_rank()) return a;
  const Eigen::VectorXd& s = svd.singularValues();
  const Eigen::MatrixXd W = svd.matrixV() * s.cwiseAbs2().cwiseInverse().asDiagonal() * svd.matrixV().transpose();
  a.covariance = sigma0_squared * (scale.asDiagonal() * W * scale.asDiagonal());
  a.uncertainty = a.covariance.diagonal().cwiseSqrt();
  a.correlation = Eigen::MatrixXd::Identity(p, p);
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = 0; j < p; ++j)
      if (i != j) a.correlation(i, j) = a.covariance(i, j) / std::sqrt(a.covariance(i, i) * a.covariance(j, j));
  return a;
}

}  // namespace mtcal
