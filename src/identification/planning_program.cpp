// Planning a probing measurement: the probe cycle's touches, contacts back to measurements, the time estimate.
#include "mtcal/identification/planning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <tuple>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/fitting/fit.hpp"
#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "probing_model.hpp"
#include "planning_common.hpp"

namespace mtcal {

using namespace planning_detail;  // the shared helpers of the planning units

namespace {

// Unit direction in axis-value space (X, Y, Z values) that moves the tool along machine axis
// `machine_axis` (0 x, 1 y, 2 z) by +1: the linear axis along it, with its direction's sign.
Vec3 axis_space(const Machine& m, const std::vector<std::size_t>& lin, int machine_axis) {
  Vec3 u = Vec3::Zero();
  for (std::size_t k = 0; k < lin.size() && k < 3; ++k)
    if (m.axes[lin[k]].direction_axis == machine_axis) u[static_cast<Eigen::Index>(k)] = m.axes[lin[k]].direction_sign;
  return u;
}

}  // namespace

std::vector<ProbeTouch> probe_touches(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c) {
  for (const auto& [name, v] : {std::pair{"ball diameter", c.ball_diameter}, std::pair{"tip diameter", c.tip_diameter},
                                std::pair{"approach", c.approach}, std::pair{"overtravel", c.overtravel},
                                std::pair{"clearance", c.clearance}})
    if (!(v > 0) || !std::isfinite(v)) throw InputError({name, 0, ""}, fmt::format("expected > 0 mm, found {:g}", v));
  if (c.touches_per_ball != 4 && c.touches_per_ball != 5)
    throw InputError({"touches per ball", 0, ""}, fmt::format("expected 4 or 5, found {}", c.touches_per_ball));
  const auto lin = linear_axes(m);
  if (lin.size() != 3) throw InputError({m.source, 0, ""}, "a probing program needs the three linear axes X, Y, Z");
  const int t = m.tool.tool_axis;
  // Tool frame directions in axis space: up (away from the workpiece along the tool) and two
  // across it. A ball centre from 4 touches: the pole and three of the equator.
  const Vec3 up = axis_space(m, lin, t), a = axis_space(m, lin, (t + 1) % 3), b = axis_space(m, lin, (t + 2) % 3);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  const ErrorModel nominal(nominal_of(m));
  std::vector<ProbeTouch> out;
  auto at = [&](const std::vector<double>& q, const Vec3& p) {
    std::vector<double> r = q;
    for (std::size_t k = 0; k < 3; ++k) r[lin[k]] = p[static_cast<Eigen::Index>(k)];
    return r;
  };
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    const ProbingRecord& r = plan.records[i];
    const ProbeFeature::Kind kind = plan.features[r.feature].kind;
    if (kind != ProbeFeature::Kind::Ball && kind != ProbeFeature::Kind::Facet)
      throw InputError({plan.source, r.line, "kind"},
                       fmt::format("a probing program probes balls and facets, not a {}", feature_kind_name(kind)));
    const Vec3 target(r.q[lin[0]], r.q[lin[1]], r.q[lin[2]]);
    if (plan.features[r.feature].kind == ProbeFeature::Kind::Ball) {
      std::vector<Vec3> dirs{up, a, -a, b, -b};
      if (c.touches_per_ball == 4) dirs.pop_back();
      for (const Vec3& u : dirs)
        out.push_back({i, at(r.q, target + (rho + c.approach) * u), at(r.q, target + (rho - c.overtravel) * u),
                       at(r.q, target + rho * u)});
      continue;
    }
    // Facet: along the probing axis (the linear axis whose motion is most nearly along the
    // normal, as plan_targets chooses it), against the normal.
    const Vec3& n = plan.features[r.feature].normal;
    const Vec3 p0 = nominal.nominal_pose(r.q).t;
    std::size_t k = 0;
    double best_slope = 0.0;
    for (std::size_t j = 0; j < 3; ++j) {
      std::vector<double> q = r.q;
      q[lin[j]] += 1.0;
      const double slope = n.dot(nominal.nominal_pose(q).t - p0);
      if (std::abs(slope) > std::abs(best_slope)) best_slope = slope, k = j;
    }
    Vec3 u = Vec3::Zero();
    u[static_cast<Eigen::Index>(k)] = best_slope > 0 ? 1.0 : -1.0;  // the side the probe comes from
    out.push_back({i, at(r.q, target + c.approach * u), at(r.q, target - c.overtravel * u), at(r.q, target)});
  }
  return out;
}

namespace planning_detail {

std::vector<Vec3> match_contacts(const Machine& m, const ProbingPlan& plan, const std::vector<ProbeTouch>& touches,
                                 const std::vector<LoggedContact>& contacts, const ContactWording& w,
                                 const std::string& log_source) {
  const auto lin = linear_axes(m);
  const auto rot = rotary_axes(m);
  const std::string source = contacts.empty() ? log_source : contacts.front().source;
  if (contacts.size() < touches.size()) {
    // A short log: name the first contact missing, where the program stopped or a probe never
    // tripped (LinuxCNC: "G38.2 move finished without making contact", the program ends there).
    const std::size_t k = contacts.size();
    throw InputError({source, contacts.empty() ? 0 : contacts.back().line, ""},
                     fmt::format("expected {} contacts, found {}: contact {} is missing ({}): the probe did not trip "
                                 "there (LinuxCNC: G38.2 move finished without making contact) or the program stopped "
                                 "before it{}",
                                 touches.size(), k, k + 1, w.touch(k), w.missing_tail));
  }
  if (contacts.size() > touches.size())
    throw InputError({source, contacts[touches.size()].line, ""},
                     fmt::format("expected {} contacts ({}), found {}: the first extra one is on this line",
                                 touches.size(), w.moves, contacts.size()));
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& t = touches[i];
    const LoggedContact& lc = contacts[i];
    const ProbingRecord& r = plan.records[t.record];
    for (std::size_t k : rot)
      if (std::isfinite(lc.q[k]) && std::abs(lc.q[k] - r.q[k]) > 1e-6)
        throw InputError({lc.source, lc.line, std::string(1, m.axes[k].letter)},
                         fmt::format("contact {} belongs to {} at {} = {:.4f} deg, found {:.4f} deg: the log does not "
                                     "follow {}",
                                     i + 1, w.owner(i), m.axes[k].letter, r.q[k] * 180 / std::numbers::pi,
                                     lc.q[k] * 180 / std::numbers::pi, w.program));
    Vec3 p, st, e, x;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto c = static_cast<Eigen::Index>(k);
      p[c] = lc.q[lin[k]];
      st[c] = t.start[lin[k]];
      e[c] = t.end[lin[k]];
      x[c] = t.expected[lin[k]];
    }
    if (!p.allFinite())
      throw InputError({lc.source, lc.line, ""}, "expected the X, Y and Z of the contact, found them missing");
    if (w.on_move > 0) {
      // On its probing move: the log is the positions where the moves tripped (within the words'
      // decimals and a controller's following error along the move).
      const Vec3 d = (e - st).normalized();
      const double along = (p - st).dot(d), off = (p - st - along * d).norm();
      if (off > w.on_move || along < -w.on_move || along > (e - st).norm() + w.on_move)
        throw InputError({lc.source, lc.line, ""},
                         fmt::format("contact {} is {:.3f} mm off its probing move ({}): the log does not follow {}",
                                     i + 1, std::max(off, std::max(-along, along - (e - st).norm())), w.touch(i),
                                     w.program));
    } else if ((p - x).norm() > w.from_expected) {
      throw InputError({lc.source, lc.line, ""},
                       fmt::format("contact {} is {:.3f} mm from where {} expects it, more than approach + overtravel "
                                   "({:g} mm): the log does not follow {}",
                                   i + 1, (p - x).norm(), w.owner(i), w.from_expected, w.program));
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace planning_detail

ProbingPlan measurements_from_contacts(const Machine& m, const ProbingPlan& plan, const ProbeCycle& c,
                                       const std::vector<LoggedContact>& contacts, const std::string& log_source) {
  const auto touches = probe_touches(m, plan, c);
  const auto lin = linear_axes(m);
  ContactWording w;
  w.program = "the plan";
  w.moves = fmt::format("the program's probing moves for {} records", plan.records.size());
  w.touch = [&](std::size_t k) {
    const ProbeTouch& t = touches[k];
    std::size_t nth = 1;
    for (std::size_t i = k; i > 0 && touches[i - 1].record == t.record; --i) ++nth;
    return fmt::format("touch {} of the plan's record {}, line {}", nth, t.record + 1, plan.records[t.record].line);
  };
  w.owner = [&](std::size_t k) {
    const std::size_t r = touches[k].record;
    return fmt::format("the plan's record {} (line {})", r + 1, plan.records[r].line);
  };
  w.from_expected = c.approach + c.overtravel;
  const std::vector<Vec3> at = match_contacts(m, plan, touches, contacts, w, log_source);
  ProbingPlan out = plan;
  out.measured = true;
  out.source = contacts.empty() ? std::string("probe log") : contacts.front().source;
  std::vector<std::vector<Point3>> ball(plan.records.size());
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& t = touches[i];
    if (plan.features[plan.records[t.record].feature].kind == ProbeFeature::Kind::Ball) {
      ball[t.record].push_back(at[i]);
    } else {
      for (std::size_t k = 0; k < 3; ++k) out.records[t.record].q[lin[k]] = at[i][static_cast<Eigen::Index>(k)];
    }
  }
  for (std::size_t i = 0; i < plan.records.size(); ++i) {
    if (ball[i].empty()) continue;
    const auto fit = fit_sphere(ball[i]);
    if (!fit)
      throw InputError({out.source, 0, ""},
                       fmt::format("the touches of the plan's record {} (line {}) do not define a sphere", i + 1,
                                   plan.records[i].line));
    for (std::size_t k = 0; k < 3; ++k) out.records[i].q[lin[k]] = fit->centre[static_cast<Eigen::Index>(k)];
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

std::pair<std::size_t, double> probe_safe_retract(const Machine& m) {
  std::size_t tz = m.axes.size();
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (m.axes[k].kind == AxisKind::Linear && m.axes[k].direction_axis == m.tool.tool_axis) tz = k;
  if (tz == m.axes.size() || !m.axes[tz].travel)
    throw InputError({m.source, 0, ""}, "the linear axis along the tool needs a travel (its end is the safe retract)");
  const Axis& z = m.axes[tz];
  return {tz, z.direction_sign > 0 ? z.travel->max : z.travel->min};
}

TimeEstimate estimate_time(const Machine& m, const ProbingPlan& given, const ProbeCycle& cycle, const TimingOptions& o) {
  for (const auto& [name, v] : {std::pair{"rapid", o.rapid}, std::pair{"rotary speed", o.rotary_speed},
                                std::pair{"probing feed", o.probe_feed}, std::pair{"move feed", o.move_feed},
                                std::pair{"ballbar feed", o.ballbar_feed}})
    if (!(v > 0) || !std::isfinite(v))
      throw InputError({name, 0, ""}, fmt::format("expected a speed > 0, found {:g}", v));
  for (const auto& [name, v] : {std::pair{"settle", o.settle}, std::pair{"ballbar setup", o.ballbar_setup},
                                std::pair{"laser setup", o.laser_setup}, std::pair{"laser dwell", o.laser_dwell}})
    if (!(v >= 0) || !std::isfinite(v))
      throw InputError({name, 0, ""}, fmt::format("expected a time >= 0 s, found {:g}", v));
  if (o.tool_point && !(o.index_step > 0 && std::isfinite(o.index_step)))
    throw InputError({"indexing step", 0, ""}, fmt::format("expected > 0 rad, found {:g}", o.index_step));
  TimeEstimate t;
  // The instruments, by hand: a circle's setup and its run both ways at the ballbar feed; a line's
  // setup and per target the step at the rapid feed and the dwell.
  for (const InstrumentSetup& s : instrument_setups(m, given)) {
    if (s.kind == ProbeFeature::Kind::Ballbar) {
      t.instruments += o.ballbar_setup + 2 * (2 * std::numbers::pi * s.radius) / (o.ballbar_feed / 60.0);
      ++t.circles;
    } else {
      const double step = s.readings > 1 ? (s.to - s.from) / static_cast<double>(s.readings - 1) : 0.0;
      t.instruments += o.laser_setup + static_cast<double>(s.readings) * (step / (o.rapid / 60.0) + o.laser_dwell);
      ++t.lines;
    }
  }
  t.total = t.instruments;
  const ProbingPlan plan = probing_part(given);
  if (plan.records.empty()) return t;
  const std::vector<ProbeTouch> touches = probe_touches(m, plan, cycle);
  const auto [tz, safe] = probe_safe_retract(m);
  const auto rot = rotary_axes(m);
  const auto lin = linear_axes(m);
  std::optional<ToolPointCoordinates> world;
  if (o.tool_point) {
    try {
      world.emplace(m);
    } catch (const ModelError& e) {
      throw InputError({m.source, 0, ""}, std::string("no tool-point coordinates for this machine: ") + e.what());
    }
  }
  const double rapid = o.rapid / 60.0, feed = o.move_feed / 60.0, probe = o.probe_feed / 60.0;  // mm/s
  const double rotary = o.rotary_speed / 60.0 * std::numbers::pi / 180.0;                      // rad/s
  // The program's coordinates of axis values q: the axis values, or (tool-point) the world position
  // of their nominal tool point (the words probe_program writes).
  auto pos = [&](const std::vector<double>& q) { return world ? world->world(q) : q; };
  // G0: every axis at its rapid (the rotary ones at rotary_speed), the largest change sets the time;
  // G1 and the probing move: the feed along the path of the linear axes (RS274/NGC feed rate mode
  // G94, LinuxCNC's G1). Both in the program's coordinates, as the controller plans them.
  auto g0 = [&](const std::vector<double>& a, const std::vector<double>& b) {
    const auto pa = pos(a), pb = pos(b);
    double d = 0.0, r = 0.0;
    for (std::size_t k : lin) d = std::max(d, std::abs(pb[k] - pa[k]));
    for (std::size_t k : rot) r = std::max(r, std::abs(pb[k] - pa[k]));
    return std::max(d / rapid, r / rotary);
  };
  auto path = [&](const std::vector<double>& a, const std::vector<double>& b) {
    const auto pa = pos(a), pb = pos(b);
    double d = 0.0;
    for (std::size_t k : lin) d += (pb[k] - pa[k]) * (pb[k] - pa[k]);
    return std::sqrt(d);
  };
  const double rho = (cycle.ball_diameter + cycle.tip_diameter) / 2;
  const double sign = m.axes[tz].direction_sign;
  std::vector<double> at;  // the axes' position (chain order); empty before the first record
  std::size_t current = plan.records.size();
  const ProbingRecord* last = nullptr;
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& tt = touches[i];
    const ProbingRecord& r = plan.records[tt.record];
    const bool ball = plan.features[r.feature].kind == ProbeFeature::Kind::Ball;
    std::vector<double> over = tt.start;
    over[tz] = safe;
    if (tt.record != current) {
      current = tt.record;
      if (!at.empty()) {
        std::vector<double> up = at;
        up[tz] = safe;
        t.moves += g0(at, up);
        double index = 0.0;
        for (std::size_t k : rot) index = std::max(index, std::abs(r.q[k] - last->q[k]));
        if (index > 0) {
          if (world) {
            // Blocks of at most index_step that hold the linear axes at the safe level: each a G0
            // whose world words swing with the rotary ones.
            const auto steps = static_cast<std::size_t>(std::ceil(index / o.index_step - 1e-9));
            std::vector<double> from = up;
            for (std::size_t j = 1; j <= steps; ++j) {
              std::vector<double> q = up;
              for (std::size_t k : rot)
                q[k] = up[k] + (r.q[k] - up[k]) * static_cast<double>(j) / static_cast<double>(steps);
              t.indexing += g0(from, q);
              from = q;
            }
            t.indexing += o.settle;
          } else {
            t.indexing += index / rotary + o.settle;
          }
          ++t.indexations;
        }
        for (std::size_t k : rot) up[k] = r.q[k];
        t.moves += g0(up, over);
      } else {
        ++t.indexations;
      }
      last = &r;
      // A G0 down to the clearance level (above the ball, or clearance above a facet's start),
      // then G1 for the last of the approach.
      std::vector<double> down = tt.start;
      down[tz] = probe_clearance_level(m, plan, r, tt, cycle);
      t.moves += g0(over, down);
      at = down;
    } else if (ball) {
      // Between a ball's touches: up to the clearance level above it, over the next start.
      std::vector<double> lift = at, above = tt.start;
      lift[tz] = above[tz] = r.q[tz] + sign * (rho + cycle.clearance);
      t.moves += (path(at, lift) + path(lift, above)) / feed;
      at = above;
    }
    t.moves += path(at, tt.start) / feed;
    const double approach = path(tt.start, tt.expected);
    t.probing += approach / probe + approach / feed;
    ++t.touches;
    at = tt.start;
  }
  std::vector<double> up = at;
  up[tz] = safe;
  t.moves += g0(at, up);
  t.total = t.moves + t.probing + t.indexing + t.instruments;
  return t;
}

double probe_clearance_level(const Machine& m, const ProbingPlan& plan, const ProbingRecord& r, const ProbeTouch& first,
                             const ProbeCycle& cycle) {
  const auto [tz, safe] = probe_safe_retract(m);
  const double sign = m.axes[tz].direction_sign;
  const double rho = (cycle.ball_diameter + cycle.tip_diameter) / 2;
  const double level = plan.features[r.feature].kind == ProbeFeature::Kind::Ball
                           ? r.q[tz] + sign * (rho + cycle.clearance)
                           : first.start[tz] + sign * cycle.clearance;
  // Never beyond the safe end, never below the start (a start above the clearance level: no G0 down).
  return sign * (level - safe) > 0 ? safe : sign * (level - first.start[tz]) < 0 ? first.start[tz] : level;
}

}  // namespace mtcal
