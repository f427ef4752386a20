// Rank, conditioning and covariance of a least-squares Jacobian: one SVD-based analysis for every fit.
#pragma once

#include <cstddef>

#include <Eigen/Core>

namespace mtcal {

struct JacobianOptions {
  // A singular value s_i counts towards the rank when s_i > relative_tolerance * s_max (of the
  // column-scaled matrix when scale_columns).
  double relative_tolerance = 1e-10;
  // Divide every column by its norm before the SVD (column equilibration), so that rank and
  // condition do not depend on the parameters' units (mm against rad); the covariance is scaled
  // back. A zero column is left as it is (and makes the rank deficient).
  bool scale_columns = true;
};

struct JacobianAnalysis {
  std::size_t rank = 0;
  Eigen::VectorXd singular_values;  // min(rows, cols) of them, decreasing, of the (scaled) Jacobian
  double condition = 0.0;           // s_max / s_min; infinity when a singular value is below the tolerance
  // sigma0^2 (J^T J)^-1 = sigma0^2 D V S^-2 V^T D (D the column scaling; Golub & Van Loan,
  // Matrix Computations, 5.3). NaN everywhere when rank-deficient: no uncertainty exists, and NaN
  // says so rather than a false number.
  Eigen::MatrixXd covariance;
  Eigen::VectorXd uncertainty;  // sqrt of the covariance's diagonal (standard uncertainties)
  Eigen::MatrixXd correlation;  // cov_ij / (u_i u_j), 1 on the diagonal; NaN when rank-deficient
  std::size_t columns = 0;
  // Every unknown determined: rank equal to the number of columns.
  bool full_rank() const { return rank == columns && rank > 0; }
};

// Analyses the Jacobian J (rows: weighted residuals, columns: unknowns) of a least-squares fit at
// its solution; sigma0_squared is the variance of unit weight (e.g. SSR / degrees of freedom).
// J must be finite and have at least as many rows as columns for a full rank.
JacobianAnalysis analyse_jacobian(const Eigen::MatrixXd& J, double sigma0_squared, const JacobianOptions& options = {});

}  // namespace mtcal
