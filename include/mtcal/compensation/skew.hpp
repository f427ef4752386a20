// Axis skew (squareness) compensation of open printer/CNC firmware: Klipper SET_SKEW / skew profiles, Marlin M852.
#pragma once

#include <string>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// The firmware's shear model (Marlin planner.h skew()/unskew(), ported by Klipper as
// klippy/extras/skew_correction.py calc_skew()/calc_unskew()): the position reached from a
// command (x, y, z) is x + y·xy + z·xz, y + z·yz, z; the firmware sends
// x − y·xy − z·(xz − xy·yz), y − z·yz, z so that the programmed point is reached.
// The factors are errors per unit length: xy = ∂e_x/∂y, xz = ∂e_x/∂z, yz = ∂e_y/∂z (e = actual − nominal).
struct SkewFactors {
  double xy = 0.0, xz = 0.0, yz = 0.0;
};

struct SkewCompensation {
  SkewFactors factors;
  CompensationSummary summary;
};

// The factors of a machine with linear axes X, Y, Z along +x, +y, +z, from its squareness errors
// (the orientation location errors of the linear axes, EC0Y EB0Z EA0Z ...), the residual by the
// firmware's rule, and every other error listed as not held. `target` is "klipper" or "marlin".
// Throws InputError for another axis layout and when the model has no squareness to compensate.
SkewCompensation compensate_skew(const Machine& m, const CompensationOptions& o, const std::string& target);

// The firmware's command for a programmed point (calc_skew), and the point reached from a command
// (calc_unskew): the rule the residual and the tests apply.
Vec3 skew_command(const SkewFactors& f, const Vec3& programmed);
Vec3 skew_reached(const SkewFactors& f, const Vec3& command);

}  // namespace mtcal
