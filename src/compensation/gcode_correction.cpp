#include "mtcal/compensation/gcode_correction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/kinematics/transform.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/request_error.hpp"

namespace mtcal {
namespace {

// The tool-point rows of the least-squares system weigh this much per mm against the
// orientation rows (per rad) and the damping rows: the tool point is solved exactly (its
// residual is below 1e-15 mm for orientation errors of 1e-3 rad) and the orientation as well as
// the rotary axes allow.
constexpr double kPositionWeight = 1e6;
// Interior points of a piece where its deviation is checked: u = j / kParts, j = 1 .. kParts - 1.
constexpr int kParts = 8;
// Finite-difference steps of the solver's Jacobian, program units (mm, deg). The actual pose
// is smooth at this scale (polynomials, Fourier series; a table's kink only slows the
// convergence, whose test is on the residual itself).
constexpr double kStepLinear = 1e-3, kStepRotary = 1e-3;
// The Jacobian is recomputed when the solver is this far (mm, deg) from where it was computed.
constexpr double kJacobianReach = 5.0;

// Whether any motion error of the machine depends on the direction of motion (a reversal term,
// a backward table that differs from the forward one).
bool direction_dependent(const Machine& m) {
  for (const Axis& ax : m.axes)
    for (const MotionFunction& f : ax.motion) {
      const auto& form = f.form();
      if (const auto* p = std::get_if<Polynomial>(&form); p && p->reversal != 0) return true;
      if (const auto* fs = std::get_if<Fourier>(&form); fs && fs->reversal != 0) return true;
      if (const auto* t = std::get_if<Table>(&form); t && !t->backward.empty() && t->backward != t->forward)
        return true;
    }
  return false;
}

double sign_of(double d) { return d > 0 ? 1.0 : (d < 0 ? -1.0 : 0.0); }

std::string where_of(const std::string& source, int line) { return fmt::format("{}:{}", source, line); }

std::string show_position(const GcodePosition& p, const ProgramAxes& axes) {
  std::string s;
  for (std::size_t k = 0; k < axes.size(); ++k)
    s += fmt::format("{}{}={:.6f}", s.empty() ? "" : " ", kGcodeAxes[axes.slot(k)], p[axes.slot(k)]);
  return s;
}

// Solves actual(x) = nominal(target) for the solved axes, by Gauss-Newton on a least-squares
// system: tool point (3 rows, weighted), tool direction (2 rows: the rotation error about the
// two directions across the tool axis; the rotation about the tool axis is the spindle's), and
// a damping row per solved rotary axis. With only the linear axes solved it is Newton's method
// on the tool point.
class Solver {
 public:
  Solver(const ErrorModel& model, const ProgramAxes& axes, const GcodeCorrectionOptions& o)
      : model_(model), axes_(axes), o_(o), q_(axes.size()) {
    const Machine& m = model.machine();
    bool has[3] = {false, false, false};
    bool any_rotary = false;
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      if (m.axes[k].kind == AxisKind::Linear) {
        if (axes.slot(k) < 3) has[axes.slot(k)] = true;
        unknown_.push_back(k);
      } else {
        any_rotary = true;
      }
    }
    if (!has[0] || !has[1] || !has[2])
      throw ModelError(
          fmt::format("a corrected program needs the linear axes X, Y and Z to place the tool point; "
                      "machine '{}' ({}) lacks one",
                      m.name, m.topology.chain));
    linear_ = unknown_.size();
    if (o.orientation && any_rotary)
      for (std::size_t k = 0; k < m.axes.size(); ++k)
        if (m.axes[k].kind == AxisKind::Rotary) unknown_.push_back(k);
    rows_ = 3 + (unknown_.size() > linear_ ? 2 + (unknown_.size() - linear_) : 0);
    tool_axis_ = Vec3::Zero();
    tool_axis_[m.tool.tool_axis] = 1.0;
  }

  bool orientation() const { return unknown_.size() > linear_; }

  Vec3 nominal_point(const GcodePosition& p) {
    axes_.joints(p, q_);
    return model_.nominal_pose(q_).t;
  }
  Vec3 actual_point(const GcodePosition& p, std::span<const std::int8_t> dir) {
    axes_.joints(p, q_);
    return model_.actual_pose(q_, dir).t;
  }

  struct Outcome {
    GcodePosition cmd;
    int iterations = 0;
    double residual = 0;     // mm
    double orientation = 0;  // rad, across the tool axis
  };

  Outcome solve(const GcodePosition& target, const GcodePosition& guess, std::span<const std::int8_t> dir,
                const std::string& where) {
    axes_.joints(target, q_);
    const Affine nominal = model_.nominal_pose(q_);
    target_ = target;
    tp_ = nominal.t;
    tR_ = nominal.R;
    const Vec3 d = nominal.R * tool_axis_;
    // Two unit vectors across the tool direction.
    const Vec3 a = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    u1_ = d.cross(a).normalized();
    u2_ = d.cross(u1_);

    Outcome out;
    GcodePosition p = guess;
    Eigen::VectorXd F(rows_);
    double last_step = std::numeric_limits<double>::infinity();
    for (int it = 0;; ++it) {
      residual(p, dir, F);
      out.residual = F.head<3>().norm() / kPositionWeight;
      const double rest = F.size() > 3 ? F.tail(F.size() - 3).norm() : 0.0;
      // Converged: the tool point within tolerance and, with the orientation solved too, the
      // system stationary (the last step below a nanometre / nano-degree) or exactly met.
      if (out.residual <= o_.tolerance && (!orientation() || rest <= 1e-15 || last_step <= 1e-9)) break;
      if (it >= o_.max_iterations)
        throw InputError({where, 0, ""},
                         fmt::format("the commanded position for the programmed point {} did not converge: the tool "
                                     "point is still {:.3g} mm from its target after {} iterations (expected {:.3g} "
                                     "mm; the machine's errors may be too large, or the point near a singularity)",
                                     show_position(target, axes_), out.residual, it, o_.tolerance));
      if (!have_jacobian_ || far_from_jacobian(p)) jacobian(p, dir);
      Eigen::VectorXd step = qr_.solve(-F);
      double size = step.cwiseAbs().maxCoeff();
      if (it > 0 && size > 0.5 * last_step && !fresh_) {
        // Slow convergence with an old Jacobian: take one at this point.
        jacobian(p, dir);
        step = qr_.solve(-F);
        size = step.cwiseAbs().maxCoeff();
      }
      fresh_ = false;
      if (!std::isfinite(size))
        throw InputError({where, 0, ""}, fmt::format("the solver for the programmed point {} found no finite step "
                                                     "(a singular configuration?)",
                                                     show_position(target, axes_)));
      for (std::size_t j = 0; j < unknown_.size(); ++j)
        p[axes_.slot(unknown_[j])] += step[static_cast<Eigen::Index>(j)];
      last_step = size;
      out.iterations = it + 1;
    }
    out.cmd = p;
    if (orientation()) {
      axes_.joints(p, q_);
      const Vec3 r = rotation_vector(model_.actual_pose(q_, dir).R * tR_.transpose());
      out.orientation = std::hypot(u1_.dot(r), u2_.dot(r));
    }
    return out;
  }

 private:
  void residual(const GcodePosition& p, std::span<const std::int8_t> dir, Eigen::VectorXd& F) {
    axes_.joints(p, q_);
    const Affine A = model_.actual_pose(q_, dir);
    F.head<3>() = kPositionWeight * (A.t - tp_);
    if (!orientation()) return;
    const Vec3 r = rotation_vector(A.R * tR_.transpose());
    F[3] = u1_.dot(r);
    F[4] = u2_.dot(r);
    for (std::size_t j = linear_; j < unknown_.size(); ++j) {
      const std::size_t k = unknown_[j];
      F[static_cast<Eigen::Index>(5 + j - linear_)] = o_.rotary_damping * (axes_.joint(k, p) - axes_.joint(k, target_));
    }
  }

  bool far_from_jacobian(const GcodePosition& p) const {
    for (std::size_t s = 0; s < 6; ++s)
      if (std::abs(p[s] - jacobian_at_[s]) > kJacobianReach) return true;
    return false;
  }

  void jacobian(const GcodePosition& p, std::span<const std::int8_t> dir) {
    const auto n = static_cast<Eigen::Index>(unknown_.size());
    Eigen::MatrixXd J(rows_, n);
    Eigen::VectorXd Fp(rows_), Fm(rows_);
    for (Eigen::Index j = 0; j < n; ++j) {
      const std::size_t k = unknown_[static_cast<std::size_t>(j)];
      const double h = static_cast<std::size_t>(j) < linear_ ? kStepLinear : kStepRotary;
      GcodePosition pp = p, pm = p;
      pp[axes_.slot(k)] += h;
      pm[axes_.slot(k)] -= h;
      residual(pp, dir, Fp);
      residual(pm, dir, Fm);
      J.col(j) = (Fp - Fm) / (2 * h);
    }
    qr_.compute(J);
    jacobian_at_ = p;
    have_jacobian_ = true;
    fresh_ = true;
  }

  const ErrorModel& model_;
  const ProgramAxes& axes_;
  const GcodeCorrectionOptions& o_;
  std::vector<double> q_;
  std::vector<std::size_t> unknown_;  // machine axes solved: the linear ones, then the rotary ones
  std::size_t linear_ = 0;
  Eigen::Index rows_ = 3;
  Vec3 tool_axis_;
  GcodePosition target_{};
  Vec3 tp_, u1_, u2_;
  Mat3 tR_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
  GcodePosition jacobian_at_{};
  bool have_jacobian_ = false, fresh_ = false;
};

class Corrector {
 public:
  Corrector(const ErrorModel& model, const GcodeProgram& program, const GcodeCorrectionOptions& o)
      : model_(model),
        program_(program),
        o_(o),
        axes_(model.machine(), o.origin),
        solver_(model, axes_, o),
        n_(axes_.size()),
        state_dir_(n_, 0),
        directional_(o.directions && direction_dependent(model.machine())) {}

  GcodeCorrectionResult run() {
    if (!(std::isfinite(o_.max_deviation) && o_.max_deviation > 0))
      throw InputError({"max deviation", 0, ""},
                       fmt::format("expected a largest deviation > 0 in mm, found {}", o_.max_deviation));
    if (!(std::isfinite(o_.tolerance) && o_.tolerance > 0))
      throw InputError({"tolerance", 0, ""}, fmt::format("expected a tolerance > 0 in mm, found {}", o_.tolerance));
    if (!(std::isfinite(o_.rotary_damping) && o_.rotary_damping > 0))
      throw InputError({"rotary damping", 0, ""},
                       fmt::format("expected a rotary damping > 0, found {}", o_.rotary_damping));
    if (!program_.moves.empty()) cmd_ = tgt_ = program_.moves.front().start;
    for (const GcodeMove& mv : program_.moves) correct(mv);
    std::size_t pieces = 0;
    for (const auto& m : r_.moves) pieces += m.pieces.size();
    r_.subdivisions = pieces - r_.moves.size();
    if (r_.direction_conflicts)
      r_.warnings.push_back(fmt::format(
          "{} points where no command moves every axis in the direction its correction was solved for (a positive "
          "reversal term on an axis the correction moves back and forth): the error there keeps up to twice that "
          "reversal term",
          r_.direction_conflicts));
    if (solver_.orientation() && r_.max_orientation_left > 1e-6)
      r_.warnings.push_back(
          fmt::format("the tool orientation keeps up to {:.3g} urad of error where the rotary axes "
                      "cannot correct it (near a singularity, by the damping)",
                      r_.max_orientation_left * 1e6));
    return std::move(r_);
  }

 private:
  using Dirs = std::vector<std::int8_t>;

  std::span<const std::int8_t> dirs(const Dirs& d) const {
    return o_.directions ? std::span<const std::int8_t>(d) : std::span<const std::int8_t>();
  }

  // Solves the command for target with directions d; records the solver's figures.
  GcodePosition solve(const GcodePosition& target, const Dirs& d, int line) {
    GcodePosition guess = target;
    for (std::size_t s = 0; s < 6; ++s) guess[s] += cmd_[s] - tgt_[s];
    const auto out = solver_.solve(target, guess, dirs(d), where_of(program_.source, line));
    r_.max_iterations = std::max(r_.max_iterations, out.iterations);
    r_.max_residual = std::max(r_.max_residual, out.residual);
    r_.max_orientation_left = std::max(r_.max_orientation_left, out.orientation);
    ++r_.points_solved;
    if (o_.travel_check) {
      std::vector<double> q(n_);
      axes_.joints(out.cmd, q);
      check_joints(model_.machine(), q, where_of(program_.source, line), true);
    }
    return out.cmd;
  }

  // Directions of a straight command from a to b: the sign of each axis's motion, or d's where
  // it does not move.
  Dirs command_dirs(const GcodePosition& a, const GcodePosition& b, const Dirs& d) const {
    Dirs out = d;
    for (std::size_t k = 0; k < n_; ++k) {
      const double m = b[axes_.slot(k)] - a[axes_.slot(k)];
      if (m != 0) out[k] = static_cast<std::int8_t>(sign_of(m));
    }
    return out;
  }

  // Solves the end of a piece and the directions it is commanded with: the programmed ones,
  // then those of the command itself until they agree.
  GcodePosition solve_end(const GcodePosition& from, const GcodePosition& target, Dirs& d, int line) {
    GcodePosition cmd = solve(target, d, line);
    if (!directional_) return cmd;
    for (int round = 0; round < 3; ++round) {
      const Dirs c = command_dirs(from, cmd, d);
      if (c == d) return cmd;
      d = c;
      cmd = solve(target, d, line);
    }
    return cmd;
  }

  void correct(const GcodeMove& mv) {
    CorrectedMove cm;
    cm.line = mv.line;
    cm.motion = mv.motion;
    tgt_ = mv.start;
    if (mv.motion == GcodeMotion::Rapid) {
      Dirs d = programmed_dirs(mv.start, mv.end);
      const GcodePosition end = solve_end(cmd_, mv.end, d, mv.line);
      if (directional_ && command_dirs(cmd_, end, d) != d) ++r_.direction_conflicts;
      CorrectedPiece p;
      p.motion = GcodeMotion::Rapid;
      p.end = end;
      cm.pieces.push_back(p);
      record_correction(end, mv.end);
      const double before = (solver_.actual_point(mv.end, dirs(d)) - solver_.nominal_point(mv.end)).norm();
      r_.max_error_before = std::max(r_.max_error_before, before);
      accept_state(end, mv.end, d);
      finish(cm, mv);
      return;
    }
    const bool arc = mv.is_arc();
    cm.linearised = arc && o_.linearise_arcs;
    // Segments along which every axis moves one way: an arc turns its plane axes round at
    // every quarter of the circle.
    std::vector<double> cuts{0.0};
    if (arc && directional_ && mv.sweep != 0) {
      const PlaneAxes pa = plane_axes(mv.plane);
      const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v);
      const double a0 = std::atan2(mv.start[v] - mv.centre[v], mv.start[u] - mv.centre[u]);
      const double q = std::numbers::pi / 2;
      const double lo = std::min(a0, a0 + mv.sweep), hi = std::max(a0, a0 + mv.sweep);
      std::vector<double> ts;
      for (double k = std::ceil(lo / q); k * q <= hi; k += 1) {
        const double t = (k * q - a0) / mv.sweep;
        if (t > 1e-9 && t < 1 - 1e-9) ts.push_back(t);
      }
      std::sort(ts.begin(), ts.end());
      cuts.insert(cuts.end(), ts.begin(), ts.end());
    }
    cuts.push_back(1.0);
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) segment(mv, cuts[i], cuts[i + 1], cm);
    finish(cm, mv);
  }

  void finish(CorrectedMove& cm, const GcodeMove& mv) {
    bool changed = false;
    for (std::size_t s = 0; s < 6; ++s) changed = changed || cm.pieces.back().end[s] != mv.end[s];
    if (changed || cm.pieces.size() > 1) ++r_.moves_corrected;
    if (mv.is_arc()) ++(cm.linearised ? r_.arcs_linearised : r_.arcs_kept);
    r_.moves.push_back(std::move(cm));
  }

  // Programmed directions of a stretch a -> b: each axis's sign of motion, the state's where it
  // does not move (it keeps the side of its last motion, as the tool-path simulation has it).
  Dirs programmed_dirs(const GcodePosition& a, const GcodePosition& b) const { return command_dirs(a, b, state_dir_); }

  void record_correction(const GcodePosition& cmd, const GcodePosition& target) {
    double lin = 0;
    for (std::size_t s = 0; s < 3; ++s) lin += (cmd[s] - target[s]) * (cmd[s] - target[s]);
    r_.max_correction = std::max(r_.max_correction, std::sqrt(lin));
    for (std::size_t s = 3; s < 6; ++s)
      r_.max_rotary_correction = std::max(r_.max_rotary_correction, std::abs(cmd[s] - target[s]));
  }

  void accept_state(const GcodePosition& cmd, const GcodePosition& target, const Dirs& d) {
    corrected_start_ = true;
    cmd_ = cmd;
    tgt_ = target;
    for (std::size_t k = 0; k < n_; ++k)
      if (d[k] != 0) state_dir_[k] = d[k];
  }

  // The command of a piece from a to b at progress u: a straight line, or the arc through a and
  // b about the programmed centre moved with the correction.
  GcodeMove shape(const GcodeMove& mv, double t0, double t1, const GcodePosition& a, const GcodePosition& b,
                  const GcodePosition& ta, const GcodePosition& tb) const {
    GcodeMove c;
    c.start = a;
    c.end = b;
    c.plane = mv.plane;
    if (!mv.is_arc() || o_.linearise_arcs) {
      c.motion = GcodeMotion::Linear;
      return c;
    }
    c.motion = mv.motion;
    const PlaneAxes pa = plane_axes(mv.plane);
    const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v),
               w = static_cast<std::size_t>(pa.w);
    // The programmed centre moved by the mean correction of the two ends, then onto the
    // perpendicular bisector of the commanded chord so that both ends are on one circle.
    double cu = mv.centre[u] + ((a[u] - ta[u]) + (b[u] - tb[u])) / 2;
    double cv = mv.centre[v] + ((a[v] - ta[v]) + (b[v] - tb[v])) / 2;
    const double du = b[u] - a[u], dv = b[v] - a[v];
    const double chord = std::hypot(du, dv);
    // Uncorrected ends keep the programmed centre as it is (and the program its I J K).
    const bool uncorrected = a == ta && b == tb;
    if (chord > 1e-12 && !uncorrected) {
      const double mu = (a[u] + b[u]) / 2, mvv = (a[v] + b[v]) / 2;
      const double nu = -dv / chord, nv = du / chord;
      const double h = (cu - mu) * nu + (cv - mvv) * nv;
      cu = mu + h * nu;
      cv = mvv + h * nv;
    }
    c.centre[u] = cu;
    c.centre[v] = cv;
    c.centre[w] = a[w];
    // The sweep: the commanded angle from a to b, taken round as the programmed part turns.
    const double want = mv.sweep * (t1 - t0);
    const double phi = std::atan2((a[u] - cu) * (b[v] - cv) - (a[v] - cv) * (b[u] - cu),
                                  (a[u] - cu) * (b[u] - cu) + (a[v] - cv) * (b[v] - cv));
    const double two_pi = 2 * std::numbers::pi;
    c.sweep = phi + two_pi * std::round((want - phi) / two_pi);
    return c;
  }

  // Cuts [ta, tb] of a move, along which every axis moves one way, into pieces within the
  // deviation, marching from ta: each piece as long as it may be (halved until it holds).
  void segment(const GcodeMove& mv, double ta, double tb, CorrectedMove& cm) {
    double t = ta, len = tb - ta;
    std::size_t tries = 0;
    while (t < tb) {
      double t1 = std::min(tb, t + len);
      if (tb - t1 <= 1e-12 * std::max(1.0, tb)) t1 = tb;
      if (try_piece(mv, t, t1, cm)) {
        len = std::min(2 * (t1 - t), tb - ta);
        t = t1;
      } else {
        len = (t1 - t) / 2;
      }
      if (++tries > 4 * o_.max_pieces_per_move || cm.pieces.size() > o_.max_pieces_per_move || !(len > 1e-12))
        throw RequestError({where_of(program_.source, mv.line), 0, ""},
                           fmt::format("the move cannot be cut into pieces that stay within {} mm of the programmed "
                                       "path (more than {} pieces, or pieces shorter than 1e-12 of the move); expected "
                                       "a larger largest deviation",
                                       o_.max_deviation, o_.max_pieces_per_move),
                           {"max deviation"});
    }
  }

  bool try_piece(const GcodeMove& mv, double t0, double t1, CorrectedMove& cm) {
    const GcodePosition target = t1 >= 1 ? mv.end : position_at(mv, t1);
    // The directions the piece is solved with: the programmed ones, then those of the commands
    // themselves (the reversal move's and the piece's) until they agree. Where they cannot (a
    // reversal term > 0 on an axis that the correction moves back and forth), the piece's
    // direction is kept and the reversal move's point is counted as a conflict.
    Dirs d = programmed_dirs(tgt_, target);
    GcodePosition start = cmd_, end = cmd_;
    bool transition = false;
    std::size_t conflicts = 0;
    for (int round = 0; round < 4; ++round) {
      end = solve(target, d, mv.line);
      // A reversal: an axis now moves the other way from its last motion, so the start point
      // needs the correction of the new direction; the tool stays at the programmed point while
      // the axes take it up. The program's first feed move starts where the machine is,
      // uncorrected: a move to the corrected start comes first too.
      transition = !corrected_start_;
      if (directional_)
        for (std::size_t k = 0; k < n_; ++k)
          if (state_dir_[k] != 0 && d[k] != 0 && d[k] != state_dir_[k]) transition = true;
      start = transition ? solve(tgt_, d, mv.line) : cmd_;
      if (!directional_) break;
      const Dirs piece = command_dirs(start, end, d);
      const Dirs jump = transition ? command_dirs(cmd_, start, d) : d;
      conflicts = 0;
      Dirs next = d;
      for (std::size_t k = 0; k < n_; ++k) {
        if (piece[k] != d[k])
          next[k] = piece[k];
        else if (jump[k] != d[k])
          ++conflicts;
      }
      if (next == d) break;
      if (round == 3) conflicts += 1;
      d = next;
    }
    if (transition && start == cmd_) transition = false;
    const Dirs dt = d;
    const GcodeMove c = shape(mv, t0, t1, start, end, tgt_, target);
    double worst = 0, before = 0;
    const auto dd = dirs(d);
    for (int j = 1; j < kParts; ++j) {
      const double u = static_cast<double>(j) / kParts;
      const GcodePosition want = position_at(mv, t0 + (t1 - t0) * u);
      const Vec3 nominal = solver_.nominal_point(want);
      const Vec3 actual = solver_.actual_point(position_at(c, u), dd);
      worst = std::max(worst, (actual - nominal).norm());
      before = std::max(before, (solver_.actual_point(want, dd) - nominal).norm());
    }
    if (worst > o_.max_deviation) return false;
    before = std::max(before, (solver_.actual_point(target, dd) - solver_.nominal_point(target)).norm());
    r_.max_error_before = std::max(r_.max_error_before, before);
    r_.max_deviation_after = std::max(r_.max_deviation_after, worst);
    r_.direction_conflicts += conflicts;
    if (transition) {
      CorrectedPiece tp;
      tp.motion = GcodeMotion::Linear;
      tp.end = start;
      tp.t0 = tp.t1 = t0;
      tp.transition = true;
      cm.pieces.push_back(tp);
      ++r_.transitions;
      for (std::size_t k = 0; k < n_; ++k)
        if (dt[k] != 0) state_dir_[k] = dt[k];
    }
    CorrectedPiece p;
    p.motion = c.motion;
    p.end = end;
    p.centre = c.centre;
    p.sweep = c.sweep;
    p.t0 = t0;
    p.t1 = t1;
    cm.pieces.push_back(p);
    record_correction(end, target);
    accept_state(end, target, d);
    return true;
  }

  const ErrorModel& model_;
  const GcodeProgram& program_;
  const GcodeCorrectionOptions& o_;
  ProgramAxes axes_;
  Solver solver_;
  std::size_t n_;
  GcodePosition cmd_{}, tgt_{};  // the last commanded point and the programmed point it serves
  Dirs state_dir_;
  bool directional_;              // directions on, and some error depends on them
  bool corrected_start_ = false;  // a commanded point has been solved (the program's start is not)
  GcodeCorrectionResult r_;
};

}  // namespace

GcodeCorrectionResult correct_program(const ErrorModel& model, const GcodeProgram& program,
                                      const GcodeCorrectionOptions& options) {
  return Corrector(model, program, options).run();
}

}  // namespace mtcal
