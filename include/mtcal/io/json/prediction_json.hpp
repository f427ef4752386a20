// JSON of the prediction results (regress, predict, separate, process-error): keys in docs/prediction.md.
#pragma once

#include <string>

#include "mtcal/io/json/json.hpp"
#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/process_error.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/prediction/separation.hpp"

namespace mtcal {

// One fit: model form parameters{name: value stddev at_bound identified} identifiable rss sigma
// dof r_squared aicc backward{mean max mean_relative abs_diff} loocv_rmse.
Json to_json(const FitResult& f);

// regress: file x y n fits[] skipped[model reason] best_backward best_loocv [report]. file, x
// and y name the data and its columns; n is the number of points.
Json to_json(const ModelComparison& c, const std::string& file, const std::string& x, const std::string& y,
             std::size_t n, const std::string& report = "");

// predict: model source components[name axis source] points[line input components ex ey ez]
// warnings [compensation[step offset_x offset_y offset_z]].
Json to_json(const PredictionRun& run, const PredictionModel& model);

// separate position: file kind steps[axis step distance e_pos count] fits{e_pos_x ...}.
Json to_json(const PositionSeparation& s, const std::string& file);
// separate control: file kind quantity a b steps[axis step distance <quantity>] warnings.
Json to_json(const ControlSeparation& s, const std::string& file);

// process-error: tool coefficients cut points[feed fz mean_fx mean_fy peak_fy e_prog]
// [calibration: a fit with measured[]].
Json to_json(const ProcessErrorStudy& s);

}  // namespace mtcal
