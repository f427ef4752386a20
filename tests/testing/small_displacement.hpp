// Independent first-order (small-displacement) effect of each error, from ISO definitions.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "mtcal/model/machine.hpp"

namespace mtcal::testing {

struct FirstOrderEffect {
  ErrorName error;
  Eigen::Matrix<double, 6, 1> effect;  // d(dx dy dz rx ry rz) / d(error value), workpiece frame
};

// The effect on the tool of a unit of each error of the machine, to first order, derived from
// the errors' definitions (docs/conventions.md) with nominal frames built here from scratch with
// Eigen::Isometry3d; it shares no code with src/kinematics. Same order as
// ErrorModel::error_sensitivities.
std::vector<FirstOrderEffect> small_displacement_effects(const Machine& m, std::span<const double> q);

}  // namespace mtcal::testing
