// HTML reports of the prediction commands: regression (mtcal regress --report) and workpiece error prediction (mtcal
// predict --report).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mtcal/io/text/csv.hpp"

#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// "±u" or " (at bound)" / " (not identifiable)" per parameter: name=value... (6 significant digits).
std::string fit_parameters_text(const FitResult& f);
// 6 significant digits, "-" where not finite.
std::string significant6(double v);

// What `mtcal regress DATA --x X --y Y --models M` computes from its table: the columns x_name
// and y_name of t (read from source) and every model of specs fitted and ranked. The command and a
// recorded result's report (report/recorded.hpp) both run it. Throws InputError for a missing
// column or fewer than 2 rows, Error when no model could be fitted.
struct TableRegression {
  std::vector<double> x, y;
  ModelComparison comparison;
};
TableRegression regress_table(const CsvTable& t, const std::string& source, const std::string& x_name,
                         const std::string& y_name, const std::vector<ModelSpec>& specs);

// The data with every fitted curve and the table of criteria. file: the data file (hashed; empty:
// data given in memory, no file named); x_name, y_name: its columns.
Report regression_report(const ModelComparison& c, std::span<const double> x, std::span<const double> y,
                         const std::string& file, const std::string& x_name, const std::string& y_name,
                         const std::string& command);
// That report with the data file's SHA-256 known and the test metadata shown given (the one
// above: the session's), as positioning_report.
Report regression_report(const ModelComparison& c, std::span<const double> x, std::span<const double> y,
                         const std::string& file, const std::string& file_sha256, const std::string& x_name,
                         const std::string& y_name, const std::string& command, const ReportMetadata& metadata);

// Every component per point and axis, and the table of them. model_file is hashed; points_label
// says what the points came from ("points" or "G-code"), the run's points' source is hashed.
Report prediction_report(const PredictionRun& run, const PredictionModel& model, const std::string& model_file,
                         const std::string& points_label, const std::string& command);

}  // namespace mtcal
