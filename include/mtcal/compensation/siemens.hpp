// Siemens SINUMERIK leadscrew/encoder error compensation (LEC/EEC) from a machine model: one equidistant table per
// linear axis.
#pragma once

#include <string>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One axis's table as %_N_AX_EEC_INI holds it: values $AA_ENC_COMP[0,i,AXn] at
// $AA_ENC_COMP_MIN + i·$AA_ENC_COMP_STEP up to $AA_ENC_COMP_MAX (mm). The values are errors:
// "A positive compensation value causes the corresponding machine axis to move in the negative
// direction" (SINUMERIK 808D Function Manual 01/2017, leadscrew error compensation, p. 106).
struct SiemensEecTable {
  char axis = 'X';
  int machine_axis = 1;  // AXn: n-th machine axis (X = 1, Y = 2, Z = 3, then A B C present)
  double min = 0.0, max = 0.0, step = 0.0;
  std::vector<double> values;  // mm, one per point from min to max
};

struct SiemensCompensation {
  std::vector<SiemensEecTable> tables;
  CompensationSummary summary;
};

// The most points of one table written by default: 200 (N = 0 ... 199, 808D Function Manual);
// an 840D sl allows what MD18342 $MN_MM_CEC_MAX_POINTS / MD38000 $MA_MM_ENC_COMP_MAX_POINTS set.
constexpr std::size_t kSiemensMaxPoints = 200;

// Tables of the linear axes: the tool point's error along the axis when it alone moves (others at
// the reference), the mean of both directions (the EEC table is not direction-dependent: the
// reversal half-difference is listed as not held); every error but the positioning errors listed as
// not held; the residual by the control's rule (linear interpolation, ends held).
SiemensCompensation compensate_siemens(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
