#include "mtcal/io/compensation_firmware.hpp"

#include <cmath>

#include <fmt/format.h>

namespace mtcal {

std::array<double, 3> klipper_skew_lengths(double factor, double side) {
  // Diagonals of a parallelogram with sides a = b = side and angle alpha at A:
  // AC^2 = 2 side^2 (1 + cos alpha), BD^2 = 2 side^2 (1 - cos alpha); calc_skew_factor() returns
  // tan(pi/2 - alpha) = cot alpha, so cos alpha = factor / sqrt(1 + factor^2).
  const double c = factor / std::sqrt(1.0 + factor * factor);
  return {side * std::sqrt(2.0 * (1.0 + c)), side * std::sqrt(2.0 * (1.0 - c)), side};
}

TargetOutput klipper_output(const SkewCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  const SkewFactors& f = c.factors;
  out.files.push_back(
      {"skew.cfg", fmt::format("# Written by mtcal compensate --format klipper: [include skew.cfg] in printer.cfg.\n"
                               "# Skew factors = errors per mm: the position reached from (x, y, z) is\n"
                               "# x + y*xy_skew + z*xz_skew, y + z*yz_skew (skew_correction.py, calc_unskew()).\n"
                               "[skew_correction]\n\n[skew_correction mtcal]\nxy_skew: {:.12g}\nxz_skew: {:.12g}\n"
                               "yz_skew: {:.12g}\n",
                               f.xy, f.xz, f.yz)});
  const auto xy = klipper_skew_lengths(f.xy), xz = klipper_skew_lengths(f.xz), yz = klipper_skew_lengths(f.yz);
  out.files.push_back(
      {"skew.gcode",
       fmt::format("; Written by mtcal compensate --format klipper: load the profile of skew.cfg (start G-code)\n"
                   "SKEW_PROFILE LOAD=mtcal\n"
                   "; or, the same factors as the diagonals of a 100 mm square (SET_SKEW XY=AC,BD,AD ...):\n"
                   "; SET_SKEW XY={:.9f},{:.9f},{:.9f} XZ={:.9f},{:.9f},{:.9f} YZ={:.9f},{:.9f},{:.9f}\n",
                   xy[0], xy[1], xy[2], xz[0], xz[1], xz[2], yz[0], yz[1], yz[2])});
  return out;
}

TargetOutput marlin_output(const SkewCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  const SkewFactors& f = c.factors;
  out.files.push_back(
      {"marlin.gcode", fmt::format("; Written by mtcal compensate --format marlin: skew factors (errors "
                                   "per mm; M852.cpp: I = XY, J = XZ, K = YZ;\n"
                                   "; J and K need SKEW_CORRECTION_FOR_Z), then saved to EEPROM\n"
                                   "M852 I{:.9f} J{:.9f} K{:.9f}\nM500\n",
                                   f.xy, f.xz, f.yz)});
  out.files.push_back(
      {"Configuration.h", fmt::format("// Written by mtcal compensate --format marlin: the same factors "
                                      "built into the firmware\n"
                                      "#define SKEW_CORRECTION\n#define XY_SKEW_FACTOR {:.9f}\n"
                                      "#define SKEW_CORRECTION_FOR_Z\n#define XZ_SKEW_FACTOR {:.9f}\n"
                                      "#define YZ_SKEW_FACTOR {:.9f}\n#define SKEW_CORRECTION_GCODE\n",
                                      f.xy, f.xz, f.yz)});
  return out;
}

}  // namespace mtcal
