// HTML report of a tool-path simulation: the path in 3D coloured by its error with the error vectors, the errors along
// the path, their ranges.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/report/error_map.hpp"

namespace mtcal {

// Keeps every stride-th point of a simulation for the plots, the stride doubling whenever the
// kept points would exceed the limit, so that a program of unknown length leaves an evenly
// thinned path in bounded memory. Fed as a simulate_toolpath sink.
class ToolpathPlotSampler {
 public:
  explicit ToolpathPlotSampler(std::size_t axes, std::size_t limit = 20000);
  void add(const ToolpathChunk& c);
  std::size_t size() const { return s_.size(); }
  std::size_t stride() const { return stride_; }
  std::vector<double> s_, q_, e_;  // path length, joints (size x axes), dx dy dz (size x 3)
  std::vector<int> line_;

 private:
  void thin();
  std::size_t axes_, limit_, stride_ = 1, seen_ = 0;
};

struct ToolpathReportInputs {
  std::string program;  // the G-code file
  double step = 0;      // mm, as simulated
  bool skip_rapids = false, directions = true;
  bool program_file = true;  // false: a program read from text in memory, named but not hashed
};

void write_toolpath_report(const std::string& file, const ErrorModel& model, const ToolpathSummary& summary,
                           const ToolpathPlotSampler& plot, const ToolpathReportInputs& inputs,
                           const ReportSources& sources);

}  // namespace mtcal
