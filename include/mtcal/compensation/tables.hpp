// Error tables sampled from a machine model along its axes: what every compensation writer starts from.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/error_name.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// Where one axis is sampled: `points` evenly spaced positions from start to end, in the axis's
// user unit (mm for a linear axis, deg for a rotary one), start < end.
struct AxisSampling {
  char axis = 'X';
  double start = 0.0;
  double end = 0.0;
  std::size_t points = 0;
};

// The axis's travel (a rotary axis without travel: 0 to 360 deg) at `points` positions.
// Throws ModelError if the machine has no such axis, InputError if a linear axis has no travel.
AxisSampling default_sampling(const Machine& m, char axis, std::size_t points);

// The sampled positions in the user's unit, strictly increasing, first = start and last = end
// exactly. Throws InputError (file = where, field = the axis letter) for fewer than 2 points,
// start >= end or a non-finite bound.
std::vector<double> sample_positions(const AxisSampling& s, const std::string& where);

// Direction of motion in which a table column holds: ISO 230-2's forward (+) and reverse (-)
// approaches, the `dir` of MotionFunction::value.
enum class Approach { Forward = +1, Reverse = -1 };

// One motion error of one axis (ISO 230-1 component error: EXX, EYX, ECX ...) along its own
// axis. Values are errors, e = actual - nominal (ISO 230-1 3.4, ISO 230-2 2.11), in internal
// units: mm for a translation, rad for a rotation.
struct ComponentTable {
  ErrorName error;                       // kind Motion, body = axis
  std::vector<double> position;          // user unit of the axis (mm or deg)
  std::vector<double> forward, reverse;  // e at each position for each approach
};

// The error `component` of `axis` at the sampled positions, straight from the model's motion
// function (positions converted to internal units).
ComponentTable sample_component(const Machine& m, Component component, const AxisSampling& s, const std::string& where);

// The tool point's volumetric error (actual - nominal, machine x y z in mm, rotation in rad)
// when `axis` alone moves along its sampling and every other axis stays at `reference`
// (internal units, chain order; empty = all zero).
struct JointErrorTable {
  char axis = 'X';
  std::vector<double> position;                   // user unit of the axis
  std::vector<VolumetricError> forward, reverse;  // e at each position for each approach
};

JointErrorTable sample_joint_error(const ErrorModel& model, const AxisSampling& s, std::span<const double> reference,
                                   const std::string& where);

}  // namespace mtcal
