// Error separation from machined workpieces (Yaqoob 2017 sec. 3.3-3.6): position, thermal and control errors from dimensions.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/io/csv.hpp"

namespace mtcal {

// ---- Mechanical position errors (sec. 3.3, Tables 5.3, 5.1-5.2). The machine is "blind" to its
// own position errors, so its probe reads the part without them while the CMM sees them:
// e_pos = CMM dimension - probed dimension, per step and axis, averaged over the observations
// and the features of that axis (Y1, Y2 ...).
struct PositionStep {
  int step = 0;
  char axis = 'X';
  double distance = 0;  // distance moved (mm), from the table's d_<axis> column
  double e_pos = 0;     // mean of CMM - probe (mm)
  int count = 0;        // CMM/probe pairs averaged
};
// Table: columns step, d_x, d_y, d_z, and pairs cmm_<F>, probe_<F> where F starts with the axis
// letter (cmm_Y1, probe_Y1, cmm_Z1 ...); an empty cell is "not measured in this row" (the thesis
// measures Z once per step) but must be empty in both columns of a pair. InputError naming file,
// line and column otherwise.
std::vector<PositionStep> separate_position(const TextTable& table, const std::string& source);

// ---- Thermal errors (sec. 3.5), each as printed:
// eq. 3.1/3.2 spindle tilt change e_spd = alpha - (alpha + beta)
inline double thermal_spindle_tilt(double alpha, double alpha_plus_beta) { return alpha - alpha_plus_beta; }
// eq. 3.3/3.4 table tilt change e_tt = theta - gamma
inline double thermal_table_tilt(double theta, double gamma) { return theta - gamma; }
// eq. 3.5/3.6 e_pt = (d6 - d6a) - (d5 - d5a) - e_pos
inline double thermal_position(double d6, double d6a, double d5, double d5a, double e_pos) {
  return (d6 - d6a) - (d5 - d5a) - e_pos;
}
// sec. 3.5 spindle growth e_splz = h7 - h3
inline double thermal_spindle_growth(double h7, double h3) { return h7 - h3; }

// ---- Control errors (sec. 3.6.2). One dimension of one workpiece at one step, with the other
// components already known for its machining conditions (from the models, e.g. Table 5.7).
struct DimensionRecord {
  std::string workpiece;
  int step = 0;
  char axis = 'X';
  double nominal = 0, measured = 0;
  std::optional<double> e_pf, e_pt, e_pos;
  int line = 0;
};
// Long table: workpiece, step, axis (X or Y), nominal, measured, e_pf, e_pt, e_pos (mm; the
// component cells may be empty for a workpiece that is only ever the measured side).
std::vector<DimensionRecord> read_dimension_table(const TextTable& table, const std::string& source);

// Eq. 3.11/3.12 between workpieces a and b at every step and axis both have:
//   (dev_a - dev_b) - (e_pf_a - e_pf_b) - (e_pt_a - e_pt_b) - (e_pos_a - e_pos_b)
// with dev = measured - nominal (the workpieces have different nominal sizes, Table 5.6).
// With a = W2, b = W8 it is e_ctrl(2400-100); with a = W2, b = W5, minus e_ctrl(2400-100)
// (given per step/axis in subtract), it is e_cpr of eq. 3.15.
struct ControlStep {
  int step = 0;
  char axis = 'X';
  double distance = 0;  // nominal of a
  double value = 0;
};
std::vector<ControlStep> separate_control(const std::vector<DimensionRecord>& records, const std::string& a,
                                          const std::string& b, const std::string& source,
                                          const std::map<std::pair<int, char>, double>& subtract = {});

}  // namespace mtcal
