// HTML reports of the prediction commands: regression (mtcal regress --report) and workpiece error prediction (mtcal
// predict --report).
#pragma once

#include <span>
#include <string>

#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// "±u" or " (at bound)" / " (not identifiable)" per parameter: name=value... (6 significant digits).
std::string fit_parameters_text(const FitResult& f);
// 6 significant digits, "-" where not finite.
std::string significant6(double v);

// The data with every fitted curve and the table of criteria. file: the data file (hashed; empty:
// data given in memory, no file named); x_name, y_name: its columns.
Report regression_report(const ModelComparison& c, std::span<const double> x, std::span<const double> y,
                         const std::string& file, const std::string& x_name, const std::string& y_name,
                         const std::string& command);

// Every component per point and axis, and the table of them. model_file is hashed; points_label
// says what the points came from ("points" or "G-code"), the run's points' source is hashed.
Report prediction_report(const PredictionRun& run, const PredictionModel& model, const std::string& model_file,
                         const std::string& points_label, const std::string& command);

}  // namespace mtcal
