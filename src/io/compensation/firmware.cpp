#include "mtcal/io/compensation/firmware.hpp"

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

TargetOutput rrf_output(const SkewCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  const RrfM556 m = rrf_m556(c.tangents, c.reference_length);
  out.files.push_back(
      {"rrf.gcode",
       fmt::format("; Written by mtcal compensate --format rrf: axis skew compensation for config.g (RepRapFirmware).\n"
                   "; X, Y, Z are corrections in mm over S mm (GCodes2.cpp case 556: tanXY = X/S, tanYZ = Y/S,\n"
                   "; tanXZ = Z/S); Move::AxisTransform() commands x + tanXY*y + tanXZ*z, y + tanYZ*z (P0: the X\n"
                   "; coordinate takes the XY correction). Remove any other M556 from config.g.\n"
                   "M556 S{:.9g} X{:.9g} Y{:.9g} Z{:.9g} P0\n",
                   m.s, m.x, m.y, m.z)});
  return out;
}

TargetOutput fluidnc_output(const SkewCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  const FluidncSkew s = fluidnc_skew(c.tangents, c.reference_length);
  std::string text =
      "# Written by mtcal compensate --format fluidnc: the kinematics section of the machine's config.yaml.\n"
      "# NEEDS A FLUIDNC BUILD WITH THE Skewed KINEMATICS: it is only in the unmerged pull request\n"
      "# https://github.com/bdring/FluidNC/pull/849 (src/Kinematics/Skewed.cpp), not in released FluidNC.\n"
      "# Under axis section i, offset_<j>_mm is the correction added to axis j's motors per distance_mm\n"
      "# of travel of axis i (Skewed::init(), GenericCartesian Mtx::transform()): corrections, mm.\n"
      "kinematics:\n  Skewed:\n";
  const char* names = "xyz";
  for (int i = 0; i < 3; ++i) {
    text += fmt::format("    {}:\n      distance_mm: {:.9g}\n", names[i], s.distance[i]);
    for (int j = 0; j < 3; ++j) text += fmt::format("      offset_{}_mm: {:.9g}\n", names[j], s.offset[i][j]);
  }
  out.files.push_back({"fluidnc-kinematics.yaml", std::move(text)});
  return out;
}

}  // namespace mtcal
