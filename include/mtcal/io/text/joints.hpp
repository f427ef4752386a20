// Joint values as users write them: "X=100,Y=50,B=30" (mm, deg) and grids "X=-300:300:7".
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtcal/model/joints.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// "X=100,Y=50,Z=-20,B=30,C=90" -> internal joint values in chain order; axes not named are 0.
// Throws InputError (file = where, the caller's description of the text's origin; field = the
// offending item) for unknown letters, repeats or non-numbers.
std::vector<double> parse_joint_values(const Machine& m, std::string_view spec, std::string_view where);

// A box of joint values (JointBox): "X=0:500,Y=-200:200,B=30" (lo:hi, or one value for lo = hi).
// Axes not named span everything (lo = -inf, hi = +inf, named false).
JointBox parse_box(const Machine& m, std::string_view spec, std::string_view where);

// The inverse of parse_joint_values: "X=100,B=30" for every axis, in user units (%g), joined
// by separator.
std::string format_joint_values(const Machine& m, const std::vector<double>& q, std::string_view separator = ",");

// Per-axis sample values of a grid "X=-300:300:7,B=-90:90:5" (lo:hi:count, or a single value);
// axes not named are held at 0. Internal units, chain order. Errors as parse_joint_values.
std::vector<std::vector<double>> parse_grid(const Machine& m, std::string_view spec, std::string_view where);

}  // namespace mtcal
