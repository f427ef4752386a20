// ISO 230-6 diagonal displacement tests simulated on the model: body and face diagonals of a box.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

struct DiagonalOptions {
  std::size_t points = 21;     // targets per diagonal, ends included (>= 2)
  bool face_diagonals = true;  // the 12 face diagonals besides the 4 body diagonals
};

// One diagonal: what a laser aligned with it would read. The displacement error is the tool's
// translational error projected on the diagonal's nominal direction, relative to the start
// (the laser is zeroed there): d(s) = u . (e(s) - e(0)) (ISO 230-6, 3.1 and 6).
struct DiagonalProfile {
  std::string name;                // "body PPP", "face XY Z- PP" (signs: direction along X Y Z)
  std::vector<double> start, end;  // joint values (internal units, chain order)
  Vec3 direction = Vec3::Zero();   // unit nominal direction of travel, workpiece frame
  double length = 0.0;             // mm
  std::vector<double> position;    // mm from the start, along the diagonal
  std::vector<double> deviation;   // mm
  double range = 0.0;              // max - min of the deviations, mm

  double largest_deviation() const;  // max |deviation|, mm
};

// The 4 body diagonals (PPP, NPP, PNP, PPN: the signs of travel along the first, second and
// third linear axis in X Y Z order) and the 12 face diagonals of the box [lo, hi] of joint values
// (internal units, chain order; rotary axes and anything else held at lo). Needs three linear
// axes with lo < hi; throws InputError otherwise.
std::vector<DiagonalProfile> diagonal_displacements(const ErrorModel& model, std::span<const double> lo,
                                                    std::span<const double> hi, const DiagonalOptions& options = {});

}  // namespace mtcal
