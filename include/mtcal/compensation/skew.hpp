// Axis skew (squareness) compensation of open printer/CNC firmware: Klipper SET_SKEW, Marlin M852, RepRapFirmware
// M556, FluidNC Skewed kinematics.
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

// The corrections RepRapFirmware and FluidNC hold: tangents added to the commanded coordinates,
// x_cmd = x + y·xy + z·xz, y_cmd = y + z·yz (RepRapFirmware src/Movement/Move.cpp,
// Move::AxisTransform() with M556 P0; FluidNC PR #849 Kinematics/Skewed.cpp with the offsets
// under y and z). They invert the shear of SkewFactors exactly: xy = -f.xy, yz = -f.yz,
// xz = f.xy·f.yz - f.xz.
struct SkewTangents {
  double xy = 0.0, xz = 0.0, yz = 0.0;
};
SkewTangents skew_tangents(const SkewFactors& f);

// RepRapFirmware's M556 S<len> X<dev> Y<dev> Z<dev>: GCodes2.cpp case 556 stores X/S as
// tangents[0] (tanXY), Y/S as tangents[1] (tanYZ), Z/S as tangents[2] (tanXZ).
struct RrfM556 {
  double s = 100.0, x = 0.0, y = 0.0, z = 0.0;
};
RrfM556 rrf_m556(const SkewTangents& t, double reference_length);
// Move::AxisTransform() with compensateXY = true (M556 P0, the default): the machine position
// commanded for a user position, axis X first (it reads the untransformed Y).
Vec3 rrf_command(const RrfM556& m556, const Vec3& programmed);

// FluidNC Skewed kinematics (PR #849, not in a release): per axis section i, distance_mm and
// offset_<j>_mm; the matrix row i is offset_j / distance_mm + (i == j) and the motors get
// m_j = sum_i p_i·row_i[j] (GenericCartesian::Mtx::transform()).
struct FluidncSkew {
  double distance[3] = {100.0, 100.0, 100.0};  // distance_mm of sections x, y, z
  double offset[3][3] = {};                    // offset[i][j]: section i (x y z), offset_<j>_mm
};
FluidncSkew fluidnc_skew(const SkewTangents& t, double reference_length);
Vec3 fluidnc_command(const FluidncSkew& s, const Vec3& programmed);

struct SkewCompensation {
  SkewFactors factors;
  SkewTangents tangents;          // the corrections (rrf, fluidnc)
  double reference_length = 100;  // mm: M556 S, FluidNC distance_mm
  CompensationSummary summary;
};

// The factors of a machine with linear axes X, Y, Z along +x, +y, +z, from its squareness errors
// (the orientation location errors of the linear axes, EC0Y EB0Z EA0Z ...), the residual by the
// firmware's rule, and every other error listed as not held. `target` is "klipper", "marlin",
// "rrf" or "fluidnc"; o.skew_reference_length is the length M556 S / distance_mm refer to.
// Throws InputError for another axis layout and when the model has no squareness to compensate.
SkewCompensation compensate_skew(const Machine& m, const CompensationOptions& o, const std::string& target);

// The firmware's command for a programmed point (calc_skew), and the point reached from a command
// (calc_unskew): the rule the residual and the tests apply.
Vec3 skew_command(const SkewFactors& f, const Vec3& programmed);
Vec3 skew_reached(const SkewFactors& f, const Vec3& command);

}  // namespace mtcal
