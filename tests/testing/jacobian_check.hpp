// Numeric-difference Jacobian of the volumetric error, to check analytic Jacobians against.
#pragma once

#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal::testing {

// Central differences d(dx dy dz rx ry rz)/d(parameter) with step h_i = rel_step * max(|p_i|, typical_i)
// where typical_i is a size that keeps the step meaningful for zero parameters.
Eigen::Matrix<double, 6, Eigen::Dynamic> numeric_jacobian(const Machine& m, std::span<const double> q,
                                                          std::span<const std::int8_t> dir);

}  // namespace mtcal::testing
