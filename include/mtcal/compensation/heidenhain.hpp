// HEIDENHAIN TNC nonlinear axis-error compensation from a machine model: one *.COM table per linear axis, with a
// column per compensated axis, assigned to the axes by a *.CMA table.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One *.COM table: the compensation values of the axes in `columns` as functions of the position
// of `axis` ("[axis in column of *.COM] = F(axis in whose *.CMA column the *.COM is entered)",
// MANUALplus 620 Technical Manual 01/2012, p. 718; AXISPOS relative to the machine datum, p. 716).
// Values are errors e = actual - nominal in mm (the manuals' example tabulates the measured
// "Error in Z" over Y: TNC 407 Technical Manual 01/98, 4-28); the sign the control applies is not
// confirmed by a public source and must be checked on the control.
struct HeidenhainComTable {
  char axis = 'X';                          // the axis whose position is the argument (AXISPOS)
  std::vector<double> position;             // AXISPOS, mm, strictly increasing
  std::string columns;                      // compensated axes, e.g. "XYZ"
  std::vector<std::vector<double>> values;  // values[column][position], mm
};

struct HeidenhainCompensation {
  std::vector<HeidenhainComTable> tables;  // chain order of their argument axis
  CompensationSummary summary;
};

// The most entries of one *.COM table: "Compensation value table (.COM) has more than 256 entries"
// is an error of PLC module 9095 (TNC 407 Technical Manual 01/98, 4.7.3).
constexpr std::size_t kHeidenhainMaxPoints = 256;

// Per linear axis L a table over its sampling: in L's own column the tool point's error along L
// when L alone moves (the others at the reference), in every other linear axis K's column the
// error along K caused by moving L (straightness, sag), less its value at the reference so that
// the constant is held once, by K's own table. The mean of both directions (the BACKLASH column's
// semantics are not written: the reversal half-difference is listed as not held). Rotary axes get
// no table. Residual: axis K is commanded to q_K - sum_L interpolation of the L table's K column at
// q_L (linear interpolation, ends held: assumed, see docs/compensation.md).
HeidenhainCompensation compensate_heidenhain(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
