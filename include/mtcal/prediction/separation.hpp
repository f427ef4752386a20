// Error separation from machined workpieces (Yaqoob 2017 sec. 3.3-3.6): position, thermal and control errors from
// dimensions.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/regression.hpp"

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
// One CMM/probe pair of a feature at a step (a cell pair of Table 5.3; the position table's
// reader in the formats layer, separation_file.hpp, makes them).
struct PositionObservation {
  int step = 0;
  char axis = 'X';      // the feature's axis: the first letter of its name (Y1 -> Y)
  std::string feature;  // Y1, Z1 ...
  double distance = 0;  // distance moved along the axis at this step (mm)
  double cmm = 0, probe = 0;
  int line = 0;  // source line, for messages
};
// Per step and axis (sorted by axis, then step): e_pos = mean of cmm - probe over the
// observations; the distance is that of the step's first observation of the axis.
std::vector<PositionStep> separate_position(const std::vector<PositionObservation>& observations);

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
// The long table of these records is read by the formats layer (separation_file.hpp).

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

// ---- What mtcal separate reports ----

// Position errors per step and the thesis' regressions on them (eq. 5.1-5.3): a quadratic
// through zero for X and Y, a line for Z, for each axis with at least 3 steps.
struct PositionSeparation {
  std::vector<PositionStep> steps;
  std::vector<std::pair<std::string, FitResult>> fits;  // "e_pos_x", "e_pos_y", "e_pos_z"
};
PositionSeparation separate_position_with_fits(const std::vector<PositionObservation>& observations);

// Control errors between workpieces a and b (eq. 3.11-3.12); with a model, minus its
// e_ctrl(2400-100) (eq. 3.15): the quantity is then e_cpr.
struct ControlSeparation {
  std::string quantity;  // "e_ctrl", or "e_cpr" with a model
  std::string a, b;
  std::vector<ControlStep> steps;
  std::vector<std::string> warnings;  // "line N: ..." from the model's validity ranges
};
// Eq. 3.15's subtrahend per step and axis of workpiece a: the model's e_ctrl_x / e_ctrl_y by the
// path of predict (scale, validity range, stages ...) at the nominal distance and with the feed
// ramp at its 'one_at' end (the 2400 -> 100 change the forms were fitted to, eq. 5.52-5.53).
// InputError naming the model file for a missing component or one that reads other variables.
std::map<std::pair<int, char>, double> control_model_errors(const PredictionModel& model,
                                                            const std::vector<DimensionRecord>& records,
                                                            const std::string& a, const std::string& source,
                                                            std::vector<std::string>& warnings);
ControlSeparation separate_control(const std::vector<DimensionRecord>& records, const std::string& a,
                                   const std::string& b, const std::string& source, const PredictionModel* model);

}  // namespace mtcal
