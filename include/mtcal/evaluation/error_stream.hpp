// Streamed evaluation of the volumetric error over many configurations (a list or a full grid) in bounded memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// Configurations listed one by one (the rows of a file), every row already checked.
struct ConfigurationList {
  std::size_t axes = 0;
  std::vector<double> q;         // rows x axes, internal units (mm, rad), chain order
  std::vector<std::int8_t> dir;  // rows x axes directions of motion (+1, -1, 0), or empty (none)
  std::vector<int> lines;        // source line of each row (0 where unknown)
  std::size_t size() const { return axes ? q.size() / axes : 0; }
};

// Per-axis sample values of a full grid, chain order, internal units (as parse_grid gives them).
using GridValues = std::vector<std::vector<double>>;

// Number of configurations of a grid: the product of the axes' value counts.
std::size_t grid_count(const GridValues& values);
// Refuses (InputError located in where) a grid of more than max_count configurations, and one
// whose corners lie outside the axes' travels (travel_check) or are not joint positions
// (check_joints).
void check_grid(const Machine& m, const GridValues& values, const std::string& where, bool travel_check,
                std::size_t max_count);

// Where the configurations of a stream come from: a list or a grid, configuration i filled on
// demand. Refers to the list or grid, which must outlive it.
class ConfigurationSource {
 public:
  static ConfigurationSource list(const ConfigurationList& list);
  // Mixed-radix index: the last axis of the chain varies fastest.
  static ConfigurationSource grid(const GridValues& values);

  std::size_t axes() const { return axes_; }
  std::size_t size() const { return size_; }
  bool has_directions() const { return list_ && !list_->dir.empty(); }
  // Configuration index into q (axes values) and, with directions, into dir (axes values).
  void fill(std::size_t index, double* q, std::int8_t* dir) const;
  // Configurations [first, first + count) into q (count x axes) and dir (count x axes, with
  // directions); a grid counts its digits up instead of dividing per configuration.
  void fill_range(std::size_t first, std::size_t count, double* q, std::int8_t* dir) const;
  // The grid's values, or nullptr for a list.
  const GridValues* grid_values() const { return grid_; }

 private:
  const ConfigurationList* list_ = nullptr;
  const GridValues* grid_ = nullptr;
  std::size_t axes_ = 0, size_ = 0;
};

// One evaluated stretch of the stream, as parallel arrays valid during the sink call.
struct ErrorChunk {
  std::size_t first = 0;  // index of the first configuration
  std::size_t axes = 0;
  std::span<const double> q;         // size() x axes, internal units
  std::span<const std::int8_t> dir;  // size() x axes, or empty
  std::span<const double> error;     // size() x 6: dx dy dz (mm), rx ry rz (rad), workpiece frame
  std::size_t size() const { return error.size() / 6; }
};

struct StreamOptions {
  int threads = 0;                           // 0: all cores
  std::size_t chunk = std::size_t{1} << 20;  // configurations per batch (memory ~ chunk x (axes + 6) doubles)
  // Called after each chunk with the configurations done and the total.
  std::function<void(std::size_t done, std::size_t total)> progress;
  // A grid through ErrorModel::evaluate_grid (to rounding the point kernel's numbers, at a
  // fraction of the work); false: configuration by configuration, as a list.
  bool grid_kernel = true;
};

// The largest error of a stream and where (the first configuration reaching it).
struct ErrorExtreme {
  double value = 0.0;      // |(dx, dy, dz)| in mm or |(rx, ry, rz)| in rad; 0 for no configuration
  std::vector<double> at;  // its configuration (internal units), empty for no configuration
};

struct StreamSummary {
  std::size_t count = 0;
  ErrorExtreme max_translation, max_rotation;
  double seconds = 0.0;  // spent in the model's evaluation
};

// Evaluates every configuration of source in chunks of options.chunk, calling sink (if any) on
// each evaluated chunk in order. Throws Error naming the configuration (1-based, "of count")
// where the model gives a non-finite error, before that chunk reaches the sink.
StreamSummary evaluate_stream(const ErrorModel& model, const ConfigurationSource& source,
                              const std::function<void(const ErrorChunk&)>& sink = {},
                              const StreamOptions& options = {});

}  // namespace mtcal
