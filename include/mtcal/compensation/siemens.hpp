// Siemens SINUMERIK leadscrew/encoder error compensation (LEC/EEC, one equidistant table per linear axis) and sag /
// angularity (cross-axis) compensation (CEC, one table per pair of linear axes) from a machine model.
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

// One sag/angularity compensation table as %_N_NC_CEC_INI holds it: values $AN_CEC[t,i] at
// $AN_CEC_MIN[t] + i·$AN_CEC_STEP[t] of the base axis $AN_CEC_INPUT_AXIS[t], applied to the
// compensation axis $AN_CEC_OUTPUT_AXIS[t]; both directions ($AN_CEC_DIRECTION = 0), no table
// multiplication, no modulo. The values are corrections (c = -e, mm): the control adds them to the
// position setpoint of the compensation axis ("the absolute position of another axis (compensation
// axis) must be influenced", SINUMERIK Function Manual Extended Functions, K3 Compensations
// 03/2013 6FC5397-1BP40-3BA1, 4.4.3 "Compensation of sag and angularity errors").
struct SiemensCecTable {
  char input = 'Y', output = 'X';
  int input_machine_axis = 2, output_machine_axis = 1;  // AXn as in SiemensEecTable
  double min = 0.0, max = 0.0, step = 0.0;              // base axis positions (mm)
  std::vector<double> values;                           // mm, corrections of the output axis
};

struct SiemensCompensation {
  std::vector<SiemensEecTable> tables;
  std::vector<SiemensCecTable> cec;  // NC_CEC.INI; empty: no cross-axis error to compensate
  CompensationSummary summary;
};

// The most points of one table written by default: 200 (N = 0 ... 199, 808D Function Manual);
// an 840D sl allows what MD18342 $MN_MM_CEC_MAX_POINTS / MD38000 $MA_MM_ENC_COMP_MAX_POINTS set.
constexpr std::size_t kSiemensMaxPoints = 200;
// The most CEC tables written: 8 (828D: "eight tables each with 200 interpolation points", K3
// 03/2013 4.4.4.3; an 840D sl sets the points of each table t with MD18342 $MN_MM_CEC_MAX_POINTS[t]).
constexpr std::size_t kSiemensMaxCecTables = 8;

// The tables are sampled on the errors they hold — positioning (EXX ...), straightness (EYX ...)
// and squareness (EC0Y ...) of the linear axes — with the other axes at the reference. EEC: per
// linear axis the tool point's error along it when it alone moves, the mean of both directions (the
// EEC table is not direction-dependent: the reversal half-difference is listed as not held). CEC:
// per ordered pair of linear axes (base I, compensation O) whose cross error is not zero, minus the
// tool point's error along O when I alone moves, less its value at I's reference position (the EEC
// table of O holds that), the mean of both directions. Every other error is listed as not held
// with its effect; the residual by the control's rule (linear interpolation, ends held, EEC moves
// the axis by -value, CEC by +value, all tables of an axis summed) on the whole model.
SiemensCompensation compensate_siemens(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
