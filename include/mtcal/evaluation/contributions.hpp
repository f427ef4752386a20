// Contribution of each error to a volumetric error or to a difference of two (Fletcher 2009, 4 and 5).
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// First-order contribution of one error: its effect on the tool's translational error, from the
// sensitivity of the error-free machine (the linearisation that defines each error, see
// docs/conventions.md) times the error's value at the configuration(s).
struct Contribution {
  ErrorName error;
  Vec3 effect = Vec3::Zero();  // mm: at a, or at a minus at b
  double along = 0.0;          // mm: effect projected on the direction of the exact error (difference)
  double share = 0.0;          // along / |exact|: the fractions of all errors sum to ~1
};

struct ContributionAnalysis {
  Vec3 exact = Vec3::Zero();        // e(a), or e(a) - e(b): the exact model's
  Vec3 first_order = Vec3::Zero();  // sum of the effects
  // |exact - first_order|: second order in the errors (products of two errors, and the
  // curvature of the exact transforms), so small beside |exact| for real machines.
  double residual = 0.0;
  std::vector<Contribution> items;  // every error with a non-zero effect, largest |along| first
};

// Contributions to the error at configuration a, or (with b) to e(a) - e(b). Joint values in
// internal units, chain order; dir as in ErrorModel (empty: no reversal terms).
ContributionAnalysis contributions(const Machine& m, std::span<const double> a, std::span<const std::int8_t> dir_a = {},
                                   std::optional<std::span<const double>> b = std::nullopt,
                                   std::span<const std::int8_t> dir_b = {});

// The value of an error at a configuration: a motion error's function at its axis's position
// (and direction), a location or mounting error's constant. mm or rad.
double error_value(const Machine& m, const ErrorName& error, std::span<const double> q,
                   std::span<const std::int8_t> dir = {});

// Effect of one error on the tool at a configuration, per 1 um of a translational error or per
// 1 urad of a rotational one: dx dy dz in um, rx ry rz in urad (the exact model's first-order
// sensitivity, workpiece frame).
struct ErrorEffect {
  ErrorName error;
  bool rotational = false;  // per 1 urad; else per 1 um
  std::array<double, 6> effect{};
};
// Effects of the machine's errors at q, in the order of Machine::parameters(); only those named
// in `only` when it is not empty. About the machine as given: clear its errors first for the
// errors' definitions (exact zeros where an error has no effect); with its errors the effects
// include second-order cross terms.
std::vector<ErrorEffect> single_error_effects(const Machine& m, std::span<const double> q,
                                              std::span<const ErrorName> only = {});

// The machine's parameters in Machine::parameters() order, only those with a non-zero value
// when nonzero_only.
std::vector<ErrorParameter> listed_parameters(const Machine& m, bool nonzero_only);

// Every error of the machine that has a non-zero parameter, in Machine::parameters() order.
std::vector<ErrorName> nonzero_errors(const Machine& m);
// The machine with every parameter of one error set to zero.
Machine without_error(const Machine& m, const ErrorName& error);

}  // namespace mtcal
