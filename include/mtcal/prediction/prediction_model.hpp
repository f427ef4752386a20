// Workpiece error prediction model (Yaqoob 2017 ch. 5-6): components from a YAML file, spindle-speed stages, sums per
// axis.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/prediction/regression.hpp"

namespace mtcal {

// A component's model at one measured spindle speed (a thermal stage, section 3.5.1).
struct SpeedStage {
  double speed = 0.0;  // rpm
  Model model;
  std::string source;  // citation, e.g. "eq. 5.6"
};

// Factor (v - zero_at) / (one_at - zero_at) of a variable: the thesis' feed scaling of the
// control errors measured for a feed change from 100 to 2400 mm/min (eq. 3.13-3.14, 5.54-5.55).
struct Ramp {
  std::string variable;
  double zero_at = 0.0, one_at = 1.0;
};

// One error component, e.g. e_pos_x (eq. 5.1). Its value at a point is
//   scale * ramp * f(variable) [* times-variable]
// where f is the model, the spindle-speed interpolation of the stage models, or (with 'of')
// another component's value before that component's own scale.
struct ErrorComponent {
  std::string name;
  char axis = 0;                   // 'x', 'y', 'z': summed into that axis' predicted error; 0: listed only
  std::string variable;            // driving variable (a points column: t, S, F, dx, dy, dz, e_prog ...)
  std::optional<Model> model;      // exactly one of model, stages, of
  std::vector<SpeedStage> stages;  // sorted by speed, at least 2
  std::string speed_variable = "S";
  std::string of;  // name of an earlier component (e.g. a tilt times a lever arm)
  double scale = 1.0;
  std::string times;  // variable multiplying the value (a lever arm), or ""
  std::optional<Ramp> ramp;
  std::optional<std::pair<double, double>> valid;  // validity range of 'variable'
  std::string source;                              // citation, e.g. "eq. 5.21-5.24"
  int line = 0;                                    // line in the model file
};

struct PredictionModel {
  std::string name;
  std::string file;
  std::vector<ErrorComponent> components;
  const ErrorComponent* find(const std::string& name) const;
  // Every variable the components read (driving, speed, ramp, times), sorted, each once.
  std::vector<std::string> variables() const;
};

// The YAML model file is read by the formats layer (prediction_model_file.hpp).

// Spindle-speed stages (eq. 3.7-3.10, 5.17-5.44): linear interpolation between the two
// measured stages that bracket S, and proportional scaling (S / S_stage) times the nearest
// stage below the lowest and above the highest. The thesis prints the interpolation weights
// swapped (eq. 3.7: (S - 3500)/2000 on the 3500 rpm model), which gives the 5500 rpm model at
// 3500 rpm and breaks continuity at every stage; mtcal weights each stage by its nearness, so
// that the value at a stage speed is that stage's model (docs/prediction.md). NaN for a speed
// <= 0 (predict_point refuses it).
double evaluate_stages(const std::vector<SpeedStage>& stages, double speed, double x);

// The value of every component at one point; a variable that the points do not give is an
// InputError from lookup.
struct PointPrediction {
  std::vector<double> values;         // per component, model order
  std::vector<double> raw;            // per component: before scale, ramp and times (the model's own value)
  double e[3] = {0, 0, 0};            // predicted X, Y, Z error: sum of the components of each axis
  std::vector<std::string> warnings;  // a driving variable outside its validity range, per component
};

// lookup(name) gives a variable's value at the point (or throws). A driving variable outside
// the component's validity range is extrapolated with a warning, or refused (InputError) when
// strict. A model that is undefined at the point (ln of t <= 0, NaN) and a spindle speed <= 0
// for a staged component are always refused.
PointPrediction predict_point(const PredictionModel& m, const std::function<double(const std::string&)>& lookup,
                              bool strict, const std::string& where = "");

// One component by the same path as predict_point (model or stages, validity range, speed > 0,
// scale, ramp, times; an 'of' component evaluates the one it names). InputError for a name the
// model does not have. Used where a single component is needed (eq. 3.15 in separate control).
struct ComponentValue {
  double raw = 0.0;    // the model's own value
  double value = 0.0;  // scale * ramp * raw * times
  std::vector<std::string> warnings;
};
ComponentValue evaluate_component(const PredictionModel& m, const std::string& name,
                                  const std::function<double(const std::string&)>& lookup, bool strict,
                                  const std::string& where = "");

// ---- Prediction over a table of points (what mtcal predict does) ----

// Points to predict at: a value per column (variable) per row, as read from a points file or
// made from a program's moves.
struct PredictionPoints {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // columns.size() values each
  std::vector<int> lines;                 // source line of each row
  std::string source;                     // the file the points come from

  int column(const std::string& name) const;  // index, or -1
};

// The variables the model reads that are neither a column nor a constant, sorted; and the
// components that read a variable (for messages).
std::vector<std::string> missing_variables(const PredictionModel& m, const PredictionPoints& points,
                                           const std::map<std::string, double>& constants);
std::vector<std::string> components_reading(const PredictionModel& m, const std::string& variable);

// Compensation per step (Yaqoob 2017 Table 6.1): the offset to add to the programmed dimension
// is minus the mean predicted error of the step's points.
struct CompensationOffset {
  double step = 0;
  double offset[3] = {0, 0, 0};  // x, y, z (mm)
};
// Steps in order of first appearance. InputError naming the points' source without a 'step' column.
std::vector<CompensationOffset> compensation_offsets(const PredictionPoints& points,
                                                     const std::vector<PointPrediction>& predictions);

struct PredictionRun {
  PredictionPoints points;
  std::vector<PointPrediction> predictions;      // per row
  std::vector<std::string> warnings;             // "line N: ..." per point warning
  std::vector<CompensationOffset> compensation;  // when asked for
};
// predict_point at every row: a variable comes from its column, else from constants. InputError
// for a variable that is neither (before any prediction), and as predict_point.
PredictionRun predict_points(const PredictionModel& m, const PredictionPoints& points,
                             const std::map<std::string, double>& constants, bool strict, bool compensation);

}  // namespace mtcal
