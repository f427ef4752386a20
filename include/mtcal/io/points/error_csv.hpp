// CSV and NumPy .npy files of volumetric errors: configuration lists read, evaluated errors written (eval,
// volumetric, diagonals, toolpath).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/io/text/error_keys.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

class AtomicFile;

// Configurations from a CSV file: columns named by axis letters (mm, deg; axes without a column
// at 0), optional dir<axis> columns of +1/-1/0, and the error columns of an evaluated file (read
// and ignored, so that an output reads back). Every row is checked (check_joints, with the
// travels when travel_check) before any work; errors name file, line and column.
ConfigurationList read_configurations(const Machine& m, const std::string& path, bool travel_check);

// Writes evaluated chunks of a stream as CSV: axis columns (mm, deg), dir<axis> columns when
// the stream has directions, dx dy dz (mm) rx ry rz (rad). Replaces path only on commit().
// A chunk's rows are formatted on `threads` threads (0: all cores) and written in order.
// translations_only: the columns of an error map (write_error_map_csv's), dx dy dz only.
class ErrorStreamCsv {
 public:
  ErrorStreamCsv(const std::string& path, const Machine& m, bool with_directions, int threads = 0,
                 bool translations_only = false);
  ~ErrorStreamCsv();
  void write(const ErrorChunk& chunk);
  void commit();

 private:
  const Machine& machine_;
  std::unique_ptr<AtomicFile> file_;
  int threads_ = 0;
  std::size_t errors_ = 6;                        // error columns written
  std::vector<std::unique_ptr<char[]>> buffers_;  // per-slice text, reused between chunks
};

// Writes evaluated chunks of a stream as a NumPy array file (.npy format version 1.0, as
// numpy.lib.format documents it: readable by numpy.load): one row per configuration, float64
// little-endian, columns as ErrorStreamCsv's (axes in mm and deg, dir<axis> when the stream has
// directions, dx dy dz in mm, rx ry rz in rad), named in the header's comment-free dict only by
// position; the shape is written at commit (the header is reserved at a fixed size first).
// Replaces path only on commit(). The numbers are the doubles themselves: no rounding.
class ErrorStreamNpy {
 public:
  ErrorStreamNpy(const std::string& path, const Machine& m, bool with_directions);
  ~ErrorStreamNpy();
  void write(const ErrorChunk& chunk);
  void commit();
  // The column names, in order (for the caller's messages and JSON).
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  std::vector<double> inv_;  // internal unit -> user unit, per axis
  std::vector<std::string> columns_;
  std::unique_ptr<AtomicFile> file_;
  std::size_t rows_ = 0;
  std::vector<double> buffer_;
};

// An error map as CSV: axis columns (mm, deg), dir<axis> when the map has directions, dx dy dz (mm).
void write_error_map_csv(const std::string& path, const Machine& m, const ErrorMap& map);

// Diagonal displacement profiles as CSV: diagonal, position (mm), deviation (mm).
void write_diagonals_csv(const std::string& path, const std::vector<DiagonalProfile>& diagonals);

// Tool-path points as CSV: line, n, motion, s (mm), axes in chain order (mm, deg), dx dy dz
// (mm), rx ry rz (rad). Replaces path only on commit().
class ToolpathCsv {
 public:
  ToolpathCsv(const std::string& path, const Machine& m);
  ~ToolpathCsv();
  void write(const ToolpathChunk& chunk);
  void commit();

 private:
  std::vector<double> inv_;  // internal unit -> user unit, per axis
  std::unique_ptr<AtomicFile> file_;
};

}  // namespace mtcal
