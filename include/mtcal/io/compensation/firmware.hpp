// Open-firmware skew files: a Klipper skew profile and SET_SKEW line, Marlin's M852 line and Configuration.h defines,
// RepRapFirmware's M556 line, a FluidNC Skewed kinematics snippet.
#pragma once

#include <array>

#include "mtcal/compensation/skew.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// skew.cfg ([skew_correction] and the profile [skew_correction mtcal] with xy_skew, xz_skew,
// yz_skew: klippy/extras/skew_correction.py reads stored profiles so) and skew.gcode
// (SKEW_PROFILE LOAD=mtcal, and the equivalent SET_SKEW XY=ac,bd,ad ... of a 100 mm square whose
// diagonals give the same factors through Klipper's calc_skew_factor()).
TargetOutput klipper_output(const SkewCompensation& c);

// marlin.gcode (M852 I J K, then M500) and Configuration.h (SKEW_CORRECTION, XY/XZ/YZ_SKEW_FACTOR).
TargetOutput marlin_output(const SkewCompensation& c);

// rrf.gcode: "M556 S<len> X<dev> Y<dev> Z<dev> P0" (deviations = corrections over S mm, nine
// significant digits), for config.g.
TargetOutput rrf_output(const SkewCompensation& c);

// fluidnc-kinematics.yaml: the kinematics: Skewed: section (x, y, z with distance_mm and
// offset_x_mm, offset_y_mm, offset_z_mm) of FluidNC pull request #849, with comments saying it
// needs a build with that kinematics.
TargetOutput fluidnc_output(const SkewCompensation& c);

// The lengths AC, BD, AD of a square of side `side` that Klipper's calc_skew_factor() turns into
// `factor`: a parallelogram with both sides `side` and cot(angle at A) = factor.
std::array<double, 3> klipper_skew_lengths(double factor, double side = 100.0);

}  // namespace mtcal
