// Joint values in their users' units: mm for linear axes, deg for rotary ones; range and travel checks.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// Factor from the user's joint unit (mm for linear, deg for rotary) to internal units.
double joint_unit_factor(const Axis& ax);
std::string_view joint_unit_name(const Axis& ax);
// An internal joint value back in the user's unit, rounded to 12 significant digits so that
// 30 deg reads 30 again after its trip through radians.
double to_user_units(const Axis& ax, double q);

// A box of joint values, internal units, chain order. An axis not named spans everything
// (lo = -inf, hi = +inf, named false).
struct JointBox {
  std::vector<double> lo, hi;
  std::vector<bool> named;
};

// Largest joint value accepted, in the user's unit (mm or deg): a kilometre, or 2800 turns.
constexpr double kMaxJointValue = 1e6;

// Throws InputError (file = where, field = the axis letter) if a joint value is not finite,
// beyond +-kMaxJointValue, or (with travel == true) outside its axis's travel.
void check_joints(const Machine& m, const std::vector<double>& q, const std::string& where, bool travel);

}  // namespace mtcal
