// Tool-path simulation (Fletcher 2009, 4.3): points along a G-code program and the volumetric error at each.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

struct ToolpathOptions {
  double step = 0.5;         // mm of X Y Z path between points, at most
  double angle_step = 0.5;   // deg of A B C motion between points, at most
  bool skip_rapids = false;  // leave G0 moves out (they still move the axes)
  // Machine axis positions of program zero (mm, deg), like a G54 offset: machine = program + origin.
  GcodePosition origin{};
  // Evaluate with each axis's direction of motion (the reversal terms of the motion errors);
  // false: direction 0, the mean of forward and backward.
  bool directions = true;
  bool travel_check = true;      // every point inside its axes' travels
  std::size_t chunk = 1u << 16;  // points evaluated per batch
  BatchOptions batch;
  std::string program = "program";  // where the moves come from (a file name): the location of block errors
};

// How program coordinates become the machine's joint values: joint k (chain order, internal units)
// = (p[program axis of k] + origin[that axis]) x the axis's unit factor (mm, deg -> mm, rad). The
// one mapping of the tool-path simulation, shared with whatever must invert it (the corrected
// G-code of compensation/gcode_correction.hpp).
class ProgramAxes {
 public:
  ProgramAxes(const Machine& machine, const GcodePosition& origin);
  std::size_t size() const { return slot_.size(); }
  // Program axis (index into GcodePosition, 0..5) of machine axis k.
  std::size_t slot(std::size_t k) const { return static_cast<std::size_t>(slot_[k]); }
  // User unit -> internal unit of machine axis k.
  double factor(std::size_t k) const { return factor_[k]; }
  const GcodePosition& origin() const { return origin_; }
  // Joint value of machine axis k at program position p.
  double joint(std::size_t k, const GcodePosition& p) const { return (p[slot(k)] + origin_[slot(k)]) * factor_[k]; }
  // Every joint at p into q (size() values).
  void joints(const GcodePosition& p, std::span<double> q) const;
  // The program value of machine axis k's coordinate for joint value q.
  double program(std::size_t k, double q) const { return q / factor_[k] - origin_[slot(k)]; }

 private:
  std::vector<int> slot_;
  std::vector<double> factor_;
  GcodePosition origin_{};
};

// Points of a stretch of the path, as parallel arrays. Joint values are internal units (mm,
// rad), machine chain order, row-major size() x axis count; error is size() x 6 (dx dy dz in
// mm, rx ry rz in rad, workpiece frame), filled by simulate_toolpath.
struct ToolpathChunk {
  std::vector<int> line;
  std::vector<std::int64_t> n;
  std::vector<GcodeMotion> motion;
  std::vector<double> s;  // X Y Z path length from the program's start (mm), skipped rapids left out
  std::vector<double> q;
  std::vector<std::int8_t> dir;  // per axis -1, 0, +1 (empty when directions are off)
  std::vector<double> error;
  std::size_t size() const { return s.size(); }
  void clear();
};

// Cuts moves into points: a move of X Y Z path length L and largest A B C travel R gets
// k = max(1, ceil(L / step), ceil(R / angle_step)) equal parts in its own parameter (arc length
// for arcs and helices), the points at the ends of the parts, its end point last. Moves of no
// length give no points. Rotary axes follow the move's progress linearly.
class ToolpathInterpolator {
 public:
  // Throws InputError for a step or angle step that is not a finite number > 0.
  ToolpathInterpolator(const Machine& machine, const ToolpathOptions& options);
  // Begins a move; returns false (and adds nothing) when it is a skipped rapid or has no length.
  bool start(const GcodeMove& move);
  // Appends the begun move's next points until chunk holds limit points or the move ends;
  // returns true when the move is complete.
  bool fill(ToolpathChunk& chunk, std::size_t limit);
  double path_length() const { return s_; }
  std::size_t blocks() const { return blocks_; }
  std::size_t rapids_skipped() const { return rapids_skipped_; }

 private:
  void emit(ToolpathChunk& chunk, const GcodePosition& p, double s);
  ProgramAxes axes_;
  ToolpathOptions options_;
  GcodeMove move_;
  std::size_t parts_ = 0, done_ = 0;
  double length_ = 0, s0_ = 0, s_ = 0;
  std::vector<double> last_;      // previous point's joints (internal units)
  std::vector<std::int8_t> dir_;  // last direction of motion per axis
  bool have_last_ = false;
  std::size_t blocks_ = 0, rapids_skipped_ = 0;
};

struct ToolpathSummary {
  std::size_t points = 0;
  std::size_t blocks = 0;  // moves with points
  std::size_t rapids_skipped = 0;
  double path_length = 0;                        // mm, X Y Z
  double max_error = 0;                          // largest |(dx, dy, dz)|, mm
  int max_line = 0;                              // its block's source line
  std::vector<double> max_at;                    // its joints, internal units, chain order
  std::array<std::array<double, 2>, 6> range{};  // min, max of dx dy dz rx ry rz
  GcodeCounts counts;                            // of the move source
};

// Reads, interpolates and evaluates a program in chunks of options.chunk points, calling sink
// on each evaluated chunk (it is reused afterwards). Memory does not grow with the program.
// Throws InputError (source:line) for a point outside an axis's travel when travel_check is on,
// Error for a non-finite error.
ToolpathSummary simulate_toolpath(const ErrorModel& model, MoveSource& moves, const ToolpathOptions& options,
                                  const std::function<void(const ToolpathChunk&)>& sink = {});
ToolpathSummary simulate_toolpath(const ErrorModel& model, const GcodeProgram& program, const ToolpathOptions& options,
                                  const std::function<void(const ToolpathChunk&)>& sink = {});

// Every point of a program without errors (tests, small programs).
ToolpathChunk interpolate_toolpath(const Machine& machine, const GcodeProgram& program, const ToolpathOptions& options);

}  // namespace mtcal
