// HTML reports of the error-model evaluations: a streamed evaluation (error map, distribution, largest errors), the
// error parameters, single-error effects.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// What a report names as its sources: the command that made it and its input files.
struct ReportSources {
  std::string command;                       // the command line as typed
  std::vector<std::string> parameter_files;  // hashed into the report
  std::string points_file;                   // a list of configurations, or empty
  std::string grid;                          // a grid's text, or empty
};

// A 3D cone plot of translational errors at nominal tool points (Plotly figure, µm), shared by
// the eval and volumetric reports. marks: labelled points drawn over the cones.
struct ConeSample {
  std::vector<double> q;  // internal units
  Vec3 nominal;           // tool point, workpiece frame (mm)
  Vec3 error;             // mm
};
struct PlotMark {
  std::string label;
  Vec3 nominal;
};
nlohmann::json error_cone_figure(const Machine& m, const std::vector<ConeSample>& samples,
                                 const std::vector<PlotMark>& marks, bool join_marks = false);

// The report of a streamed evaluation: collects what it shows while the chunks stream past, in
// bounded memory (every k-th configuration for the map, a thinned distribution, the 10 largest).
class ErrorStreamReport {
 public:
  ErrorStreamReport(const ErrorModel& model, std::size_t count);
  // An evaluated chunk, in stream order (an evaluate_stream sink).
  void add(const ErrorChunk& chunk);
  void write(const std::string& path, const ReportSources& sources) const;

 private:
  void add(std::size_t index, const double* q, const double* e);
  struct Sample {
    Vec3 nominal;  // tool point, workpiece frame
    double e[6];
    std::vector<double> q;
  };
  const ErrorModel& model_;
  std::size_t count_, stride_, magnitude_stride_;
  std::vector<Sample> samples_;    // for the error map
  std::vector<float> magnitudes_;  // |translation| in um, for the distribution
  std::vector<Sample> largest_;    // the 10 largest translational errors
};

// The error parameters (those listed), with a bar chart of the location and mounting errors.
void write_parameters_report(const std::string& path, const Machine& m, std::span<const ErrorParameter> listed,
                             std::size_t all, bool nonzero_only, const ReportSources& sources);

// Single-error effects at one configuration (m: the machine linearised about).
void write_effects_report(const std::string& path, const Machine& m, std::span<const double> at,
                          const std::string& around, std::span<const ErrorEffect> effects,
                          const ReportSources& sources);

}  // namespace mtcal
