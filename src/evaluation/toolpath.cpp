#include "mtcal/evaluation/toolpath.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/request_error.hpp"

namespace mtcal {
namespace {

// A block may not be cut into more points than this: a step far too fine for the path.
constexpr double kMaxPartsPerBlock = 1e9;

int program_slot(char letter) {
  for (int s = 0; s < 6; ++s)
    if (kGcodeAxes[s] == letter) return s;
  return -1;
}

}  // namespace

void ToolpathChunk::clear() {
  line.clear();
  n.clear();
  motion.clear();
  s.clear();
  q.clear();
  dir.clear();
  error.clear();
}

ProgramAxes::ProgramAxes(const Machine& machine, const GcodePosition& origin) : origin_(origin) {
  for (const Axis& ax : machine.axes) {
    slot_.push_back(program_slot(ax.letter));
    factor_.push_back(joint_unit_factor(ax));
  }
}

void ProgramAxes::joints(const GcodePosition& p, std::span<double> q) const {
  for (std::size_t k = 0; k < slot_.size(); ++k) q[k] = joint(k, p);
}

ToolpathInterpolator::ToolpathInterpolator(const Machine& machine, const ToolpathOptions& options)
    : axes_(machine, options.origin), options_(options) {
  if (!(std::isfinite(options.step) && options.step > 0))
    throw InputError({"step", 0, ""}, fmt::format("expected a step > 0 in mm, found {}", options.step));
  if (!(std::isfinite(options.angle_step) && options.angle_step > 0))
    throw InputError({"angle step", 0, ""},
                     fmt::format("expected an angle step > 0 in deg, found {}", options.angle_step));
  last_.assign(axes_.size(), 0.0);
  dir_.assign(axes_.size(), 0);
}

bool ToolpathInterpolator::start(const GcodeMove& move) {
  move_ = move;
  parts_ = done_ = 0;
  if (!have_last_) {
    // The first move's start is where the axes come from.
    for (std::size_t k = 0; k < axes_.size(); ++k) last_[k] = axes_.joint(k, move.start);
    have_last_ = true;
  }
  if (move.motion == GcodeMotion::Rapid && options_.skip_rapids) {
    // The axes still moved: the next point is approached from this rapid's direction.
    for (std::size_t k = 0; k < axes_.size(); ++k) {
      const std::size_t s = axes_.slot(k);
      const double d = move.end[s] - move.start[s];
      if (d != 0) dir_[k] = d > 0 ? 1 : -1;
      last_[k] = axes_.joint(k, move.end);
    }
    ++rapids_skipped_;
    return false;
  }
  length_ = mtcal::path_length(move);
  double rotary = 0;
  for (std::size_t s = 3; s < 6; ++s) rotary = std::max(rotary, std::abs(move.end[s] - move.start[s]));
  if (length_ == 0 && rotary == 0) return false;
  // ceil with a hair of slack, so that a length of exactly k steps is not cut into k + 1 parts
  // by its rounding.
  const double parts = std::max(
      {1.0, std::ceil(length_ / options_.step * (1 - 1e-12)), std::ceil(rotary / options_.angle_step * (1 - 1e-12))});
  if (!(parts <= kMaxPartsPerBlock))
    throw RequestError({options_.program, move.line, ""},
                       fmt::format("this block would need {:.3g} points (more than {:g}); expected a larger step or "
                                   "angle step between points",
                                   parts, kMaxPartsPerBlock),
                       {"step", "angle step"});
  parts_ = static_cast<std::size_t>(parts);
  s0_ = s_;
  ++blocks_;
  return true;
}

void ToolpathInterpolator::emit(ToolpathChunk& c, const GcodePosition& p, double s) {
  c.line.push_back(move_.line);
  c.n.push_back(move_.n);
  c.motion.push_back(move_.motion);
  c.s.push_back(s);
  for (std::size_t k = 0; k < axes_.size(); ++k) {
    const double q = axes_.joint(k, p);
    // The direction in which the axis arrived here: from the previous point. An axis at rest
    // keeps the side of its last motion, as its backlash does.
    if (q != last_[k]) dir_[k] = q > last_[k] ? 1 : -1;
    last_[k] = q;
    c.q.push_back(q);
    if (options_.directions) c.dir.push_back(dir_[k]);
  }
}

bool ToolpathInterpolator::fill(ToolpathChunk& chunk, std::size_t limit) {
  while (done_ < parts_ && chunk.size() < limit) {
    ++done_;
    const double t = static_cast<double>(done_) / static_cast<double>(parts_);
    const bool last = done_ == parts_;
    emit(chunk, last ? move_.end : position_at(move_, t), last ? s0_ + length_ : s0_ + length_ * t);
  }
  if (done_ < parts_) return false;
  s_ = s0_ + length_;
  return true;
}

namespace {

using NextMove = std::function<bool(GcodeMove&)>;

ToolpathSummary simulate(const ErrorModel& model, const NextMove& next, const std::string& source,
                         const ToolpathOptions& options, const std::function<void(const ToolpathChunk&)>& sink) {
  const Machine& m = model.machine();
  const std::size_t n = m.axes.size();
  const std::size_t limit = std::max<std::size_t>(1, options.chunk);
  ToolpathInterpolator interp(m, options);
  ToolpathSummary sum;
  for (auto& r : sum.range) r = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  double best = -1;

  // Bounds of each axis in internal units, with check_joints's tolerance; a point outside
  // goes to check_joints for its message.
  std::vector<double> lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    const double f = joint_unit_factor(ax);
    lo[k] = -kMaxJointValue * f;
    hi[k] = kMaxJointValue * f;
    if (options.travel_check && ax.travel) {
      const double tol = 1e-9 * std::max(1.0, std::abs(ax.travel->max - ax.travel->min));
      lo[k] = std::max(lo[k], ax.travel->min - tol);
      hi[k] = std::min(hi[k], ax.travel->max + tol);
    }
  }

  ToolpathChunk chunk;
  auto flush = [&] {
    const std::size_t len = chunk.size();
    if (len == 0) return;
    for (std::size_t i = 0; i < len; ++i)
      for (std::size_t k = 0; k < n; ++k) {
        const double q = chunk.q[i * n + k];
        if (!(q >= lo[k] && q <= hi[k]))
          check_joints(m,
                       std::vector<double>(chunk.q.begin() + static_cast<std::ptrdiff_t>(i * n),
                                           chunk.q.begin() + static_cast<std::ptrdiff_t>((i + 1) * n)),
                       fmt::format("{}:{}", source, chunk.line[i]), options.travel_check);
      }
    chunk.error.resize(len * 6);
    model.evaluate_batch(chunk.q, chunk.dir, chunk.error, options.batch);
    for (std::size_t i = 0; i < len; ++i) {
      const double* e = &chunk.error[i * 6];
      for (std::size_t c = 0; c < 6; ++c) {
        if (!std::isfinite(e[c]))
          throw Error(
              fmt::format("{}:{}: the model gives a non-finite error at a point of this block (check the "
                          "machine's error values)",
                          source, chunk.line[i]));
        sum.range[c][0] = std::min(sum.range[c][0], e[c]);
        sum.range[c][1] = std::max(sum.range[c][1], e[c]);
      }
      const double t = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      if (t > best) {
        best = t;
        sum.max_line = chunk.line[i];
        sum.max_at.assign(chunk.q.begin() + static_cast<std::ptrdiff_t>(i * n),
                          chunk.q.begin() + static_cast<std::ptrdiff_t>((i + 1) * n));
      }
    }
    sum.points += len;
    if (sink) sink(chunk);
    chunk.clear();
  };

  GcodeMove move;
  while (next(move)) {
    if (!interp.start(move)) continue;
    while (!interp.fill(chunk, limit)) flush();
    if (chunk.size() >= limit) flush();
  }
  flush();
  sum.blocks = interp.blocks();
  sum.rapids_skipped = interp.rapids_skipped();
  sum.path_length = interp.path_length();
  sum.max_error = std::max(best, 0.0);
  if (sum.points == 0) sum.range = {};
  return sum;
}

}  // namespace

ToolpathSummary simulate_toolpath(const ErrorModel& model, MoveSource& moves, const ToolpathOptions& options,
                                  const std::function<void(const ToolpathChunk&)>& sink) {
  ToolpathSummary s = simulate(
      model, [&](GcodeMove& m) { return moves.next(m); }, moves.source(), options, sink);
  s.counts = moves.counts();
  return s;
}

ToolpathSummary simulate_toolpath(const ErrorModel& model, const GcodeProgram& program, const ToolpathOptions& options,
                                  const std::function<void(const ToolpathChunk&)>& sink) {
  std::size_t i = 0;
  ToolpathSummary s = simulate(
      model,
      [&](GcodeMove& m) {
        if (i == program.moves.size()) return false;
        m = program.moves[i++];
        return true;
      },
      program.source, options, sink);
  s.counts = program.counts;
  return s;
}

ToolpathChunk interpolate_toolpath(const Machine& machine, const GcodeProgram& program,
                                   const ToolpathOptions& options) {
  ToolpathInterpolator interp(machine, options);
  ToolpathChunk out;
  for (const GcodeMove& m : program.moves)
    if (interp.start(m)) interp.fill(out, std::numeric_limits<std::size_t>::max());
  return out;
}

}  // namespace mtcal
