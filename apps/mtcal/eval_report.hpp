// The HTML report of a batched mtcal eval: error map, distribution, largest errors.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal::cli {

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

// Collects what the report shows while the batches stream past, in bounded memory.
class EvalReport {
 public:
  EvalReport(const ErrorModel& model, std::size_t count);
  // One evaluated configuration (q internal units, e = dx dy dz rx ry rz).
  void add(std::size_t index, const double* q, const double* e);
  void write(const std::string& path, const std::string& command, const std::string& points_file,
             const std::string& grid, const std::vector<std::string>& parameter_files) const;

 private:
  struct Sample {
    Vec3 nominal;      // tool point, workpiece frame
    double e[6];
    std::vector<double> q;
  };
  const ErrorModel& model_;
  std::size_t count_, stride_, magnitude_stride_;
  std::vector<Sample> samples_;        // for the error map
  std::vector<float> magnitudes_;      // |translation| in um, for the distribution
  std::vector<Sample> largest_;        // the 10 largest translational errors
};

}  // namespace mtcal::cli
