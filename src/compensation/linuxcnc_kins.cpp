#include "mtcal/compensation/linuxcnc_kins.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <variant>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

constexpr const char* kKinsTarget = "linuxcnc-kins";
constexpr std::size_t kTablePoints = 51;
// The room left between the commanded travel and the joint limits at each end, where the caller
// gives no range: kRoomFactor x the largest correction met on the pre-check grid over the whole
// travel (the grid has check_points values an axis: between its nodes a correction can be larger)
// plus kRoomFloor (the solver's tolerance and the words' decimals), rounded up to kRoomStep; widened
// up to kRoomAttempts times where the pre-check of the commanded grid still meets a corrected joint
// outside the travel. mm for linear axes, deg for rotary ones.
constexpr double kRoomFactor = 1.25;
constexpr double kRoomFloor = 0.01;
constexpr double kRoomStep = 0.001;
constexpr int kRoomAttempts = 4;

double room_for(double correction) {
  return std::ceil((kRoomFactor * correction + kRoomFloor) / kRoomStep - 1e-9) * kRoomStep;
}

// The motion function with its direction-dependent part removed: what kinematics can hold.
MotionFunction without_direction(const MotionFunction& f) {
  MotionFunction g = f;
  std::visit(
      [](auto& form) {
        using F = std::decay_t<decltype(form)>;
        if constexpr (std::is_same_v<F, Table>) {
          if (!form.backward.empty()) {
            for (std::size_t i = 0; i < form.forward.size(); ++i)
              form.forward[i] = 0.5 * (form.forward[i] + form.backward[i]);
            form.backward.clear();
          }
        } else {
          form.reversal = 0.0;
        }
      },
      g.form());
  return g;
}

bool direction_dependent(const MotionFunction& f) {
  return std::visit(
      [](const auto& form) {
        using F = std::decay_t<decltype(form)>;
        if constexpr (std::is_same_v<F, Table>) {
          return !form.backward.empty() && form.backward != form.forward;
        } else {
          return form.reversal != 0.0;
        }
      },
      f.form());
}

std::string joint_string(const Machine& m, std::span<const double> q) {
  std::string s;
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    s += fmt::format("{}{}={:.6g}", k ? "," : "", m.axes[k].letter, to_user_units(m.axes[k], q[k]));
  return s;
}

// The inverse on every configuration of a grid (chain order, internal units) with the machine
// file's tool length: the largest |corrected - commanded| per axis (internal units), and with
// check_travel the first configuration whose corrected joint leaves its travel. Not converging
// is an error (the configuration named).
struct PrecheckResult {
  struct Outside {
    std::size_t axis = 0;
    double value = 0.0;  // the corrected joint, internal units
    std::vector<double> q;
  };
  std::vector<double> largest;
  std::optional<Outside> outside;
  std::size_t checked = 0;
  int max_iterations = 0;
  double max_point_residual = 0.0;
};

PrecheckResult precheck(const Machine& m, const CommandedJointSolver& solver, const std::vector<std::vector<double>>& grid,
                        bool check_travel) {
  const std::size_t n = m.axes.size();
  PrecheckResult out;
  out.largest.assign(n, 0.0);
  std::vector<std::size_t> idx(n, 0);
  std::vector<double> q(n);
  for (bool more = true; more;) {
    for (std::size_t a = 0; a < n; ++a) q[a] = grid[a][idx[a]];
    const auto r = solver.inverse(solver.nominal_forward(q, m.tool.length), m.tool.length);
    if (!r.converged)
      throw InputError({m.source, 0, ""},
                       fmt::format("the kinematics module's inverse does not converge at {} (tool point residual "
                                   "{:.3g} mm after {} steps, cap {}): the model's errors are too large or "
                                   "ill-conditioned there",
                                   joint_string(m, q), r.point_residual, r.iterations, solver.options().max_iterations));
    for (std::size_t a = 0; a < n; ++a) {
      const Axis& ax = m.axes[a];
      const double slack = 1e-12 * std::max(1.0, ax.travel->max - ax.travel->min);
      if (check_travel && !out.outside && (r.q[a] < ax.travel->min - slack || r.q[a] > ax.travel->max + slack))
        out.outside = PrecheckResult::Outside{a, r.q[a], q};
      out.largest[a] = std::max(out.largest[a], std::abs(r.q[a] - q[a]));
    }
    out.max_iterations = std::max(out.max_iterations, r.iterations);
    out.max_point_residual = std::max(out.max_point_residual, r.point_residual);
    ++out.checked;
    more = false;
    for (std::size_t a = n; a-- > 0;) {
      if (++idx[a] < grid[a].size()) {
        more = true;
        break;
      }
      idx[a] = 0;
    }
  }
  return out;
}

}  // namespace

LinuxcncKins linuxcnc_kins_model(const Machine& m, const std::string& module_name) {
  LinuxcncKins out;
  out.module_name = module_name;
  out.machine_name = m.name;
  out.topology = m.topology.chain;
  out.workpiece_origin = m.workpiece.origin;
  out.spindle_point = m.tool.spindle_point;
  out.tool_axis = m.tool.tool_axis;
  out.tool_length = m.tool.length;
  for (const char c : std::string("XYZABC"))
    if (m.axis_index(c)) out.coordinates += c;

  // The machine at direction 0: what the module's chain evaluates.
  Machine still = m;
  for (auto& ax : still.axes)
    for (auto& f : ax.motion) f = without_direction(f);
  for (std::size_t i = 0; i < m.axes.size(); ++i) {
    const Axis& ax = still.axes[i];
    KinsAxis a;
    a.letter = ax.letter;
    a.joint = static_cast<int>(out.coordinates.find(ax.letter));
    a.rotary = ax.kind == AxisKind::Rotary;
    a.direction_axis = ax.direction_axis;
    a.direction_sign = ax.direction_sign;
    a.point = ax.point;
    a.motion = ax.motion;
    a.min = ax.travel ? ax.travel->min : 0.0;
    a.max = ax.travel ? ax.travel->max : 0.0;
    out.axes.push_back(a);
  }
  for (const ChainStep& s : actual_chain_steps(still)) {
    KinsFactor f;
    f.kind = s.kind == ChainStep::Kind::Constant ? KinsFactor::Kind::Constant
             : s.kind == ChainStep::Kind::Joint  ? KinsFactor::Kind::Joint
                                                 : KinsFactor::Kind::Motion;
    f.value = s.value;
    f.axis = s.axis;
    if (f.kind == KinsFactor::Kind::Joint) out.axes[static_cast<std::size_t>(f.axis)].zero_position = s.zero_position;
    out.chain.push_back(f);
  }

  return out;
}

LinuxcncKins compensate_linuxcnc_kins(const Machine& m, const CompensationOptions& o, const LinuxcncKinsOptions& k) {
  if (auto why = CommandedJointSolver::unsupported(m))
    throw InputError({m.source, 0, "topology"}, "a LinuxCNC kinematics module cannot represent this machine: " + *why);
  if (k.module_name.empty() || k.module_name.size() > 40 ||
      !std::all_of(k.module_name.begin(), k.module_name.end(),
                   [](char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'; }) ||
      std::isdigit(static_cast<unsigned char>(k.module_name[0])))
    throw InputError({kKinsTarget, 0, "module name"},
                     fmt::format("expected a module name of 1-40 lower-case letters, digits and '_' (a C identifier), "
                                 "found '{}'",
                                 printable(k.module_name)));
  for (const auto& ax : m.axes)
    if (!ax.travel)
      throw InputError({m.source, 0, std::string(1, ax.letter)},
                       fmt::format("expected a travel for axis {}: the module's joint limits and its pre-check grid "
                                   "come from it",
                                   ax.letter));
  LinuxcncKins out = linuxcnc_kins_model(m, k.module_name);
  out.solver = k.solver;
  Machine still = m;  // at direction 0, as in linuxcnc_kins_model
  for (auto& ax : still.axes)
    for (auto& f : ax.motion) f = without_direction(f);

  // Direction-dependent terms of each axis along/about itself: type-1 COMP_FILE corrections. The
  // error enters the chain next to the joint, along (about) the same line, so a joint change of
  // -sign * (e(q, dir) - e(q, 0)) cancels it (sign: the joint's sense against the machine axis).
  std::vector<std::string> not_in_tables;
  for (const auto& ax : m.axes) {
    for (int c = 0; c < 6; ++c) {
      if (!direction_dependent(ax.motion[static_cast<std::size_t>(c)])) continue;
      const int own = ax.kind == AxisKind::Linear ? ax.direction_axis : 3 + ax.direction_axis;
      const ErrorName name{ErrorKind::Motion, static_cast<Component>(c), ax.letter};
      if (c != own) {
        not_in_tables.push_back(name.str());
        continue;
      }
      const MotionFunction& f = ax.motion[static_cast<std::size_t>(c)];
      const MotionFunction f0 = without_direction(f);
      LinuxcncJointTable t;
      t.axis = ax.letter;
      t.joint = static_cast<int>(out.coordinates.find(ax.letter));
      const double unit = joint_unit_factor(ax);
      AxisSampling s{ax.letter, to_user_units(ax, ax.travel->min), to_user_units(ax, ax.travel->max), kTablePoints};
      if (const auto* tab = std::get_if<Table>(&f.form()); tab && tab->positions.size() <= kLinuxcncMaxCompLines) {
        for (double x : tab->positions) t.nominal.push_back(to_user_units(ax, x));
      } else {
        t.nominal = sample_positions(s, kKinsTarget);
      }
      for (double x : t.nominal) {
        const double q = x * unit, v0 = f0.value(q, 0);
        t.forward.push_back(-ax.direction_sign * (f.value(q, +1) - v0) / unit);
        t.reverse.push_back(-ax.direction_sign * (f.value(q, -1) - v0) / unit);
      }
      out.reversal_tables.push_back(std::move(t));
    }
  }
  std::sort(out.reversal_tables.begin(), out.reversal_tables.end(),
            [](const auto& a, const auto& b) { return a.joint < b.joint; });

  // The commanded travel: the caller's range of an axis where given (--range), elsewhere the travel
  // less the room the corrections need (kRoomFactor above); then the pre-check on its grid.
  const CommandedJointSolver solver(still, k.solver);
  const std::size_t n = m.axes.size();
  std::vector<bool> given(n, false);
  for (std::size_t a = 0; a < n; ++a)
    given[a] = std::any_of(o.sampling.begin(), o.sampling.end(), [&](const AxisSampling& s) { return s.axis == m.axes[a].letter; });
  auto sampling_with = [&](const std::vector<double>& margin) {
    CompensationOptions so = o;
    for (std::size_t a = 0; a < n; ++a) {
      if (given[a]) continue;
      const Axis& ax = m.axes[a];
      const double lo = to_user_units(ax, ax.travel->min) + margin[a], hi = to_user_units(ax, ax.travel->max) - margin[a];
      if (!(lo < hi))
        throw InputError({m.source, 0, std::string(1, ax.letter)},
                         fmt::format("the corrections along {} need {:g} {} of room at each end of its travel [{:g}, "
                                     "{:g}]: no commanded travel is left; the model's errors are too large for the "
                                     "travel",
                                     ax.letter, margin[a], joint_unit_name(ax), to_user_units(ax, ax.travel->min),
                                     to_user_units(ax, ax.travel->max)));
      so.sampling.push_back({ax.letter, lo, hi, k.check_points});
    }
    for (auto& s : so.sampling) s.points = std::max<std::size_t>(2, k.check_points);
    so.points = k.check_points;
    return resolve_sampling(m, so, k.check_points, 1000, kKinsTarget);
  };
  // The first guess of the room: the largest correction over the grid of the whole travel, with
  // kRoomFactor for what lies between the grid's nodes, and at least kRoomFloor.
  std::vector<double> margin(n, 0.0), travel_correction(n, 0.0);
  if (std::find(given.begin(), given.end(), false) != given.end()) {
    const PrecheckResult whole = precheck(m, solver, residual_grid(m, sampling_with(margin), k.check_points), false);
    for (std::size_t a = 0; a < n; ++a) {
      travel_correction[a] = whole.largest[a] / joint_unit_factor(m.axes[a]);
      margin[a] = room_for(travel_correction[a]);
    }
  }
  std::vector<AxisSampling> sampling;
  PrecheckResult check;
  for (int attempt = 0;; ++attempt) {
    sampling = sampling_with(margin);
    check = precheck(m, solver, residual_grid(m, sampling, k.check_points), true);
    if (!check.outside) break;
    const std::size_t a = check.outside->axis;
    const Axis& ax = m.axes[a];
    const std::vector<double> grid = residual_grid(m, sampling, k.check_points)[a];
    if (given[a] || attempt == kRoomAttempts)
      throw InputError(
          {m.source, 0, std::string(1, ax.letter)},
          fmt::format("the corrected joint {} leaves its travel [{:g}, {:g}] {}: {:.6f} at {} (commanded travel "
                      "[{:g}, {:g}]{}); leave room for the correction (a smaller range)",
                      ax.letter, to_user_units(ax, ax.travel->min), to_user_units(ax, ax.travel->max),
                      joint_unit_name(ax), to_user_units(ax, check.outside->value), joint_string(m, check.outside->q),
                      to_user_units(ax, grid.front()), to_user_units(ax, grid.back()),
                      given[a] ? "" : fmt::format(", {} tries to make room", attempt + 1)));
    // The corrections near the new ends reach farther than over the whole travel: room for what was seen.
    const double past = std::max(ax.travel->min - check.outside->value, check.outside->value - ax.travel->max);
    margin[a] = room_for(margin[a] + past / joint_unit_factor(ax));
  }
  out.largest_correction.assign(out.coordinates.size(), 0.0);
  for (std::size_t a = 0; a < n; ++a)
    out.largest_correction[out.coordinates.find(m.axes[a].letter)] = check.largest[a] / joint_unit_factor(m.axes[a]);
  out.max_iterations = check.max_iterations;
  out.max_point_residual = check.max_point_residual;
  out.checked = check.checked;
  for (std::size_t a = 0; a < n; ++a) {
    const Axis& ax = m.axes[a];
    CommandedRange r;
    r.axis = ax.letter;
    r.lo = sampling[a].start;
    r.hi = sampling[a].end;
    r.unit = std::string(joint_unit_name(ax));
    r.given = given[a];
    r.margin = given[a] ? std::max(r.lo - to_user_units(ax, ax.travel->min), to_user_units(ax, ax.travel->max) - r.hi)
                        : margin[a];
    r.largest_correction = given[a] ? check.largest[a] / joint_unit_factor(ax) : travel_correction[a];
    r.why = given[a] ? "given"
                     : fmt::format("the travel less {:g} {} each end: {:g} x the largest correction over the travel "
                                   "({:.6f} {}) + {:g} {}{}",
                                   r.margin, r.unit, kRoomFactor, r.largest_correction, r.unit, kRoomFloor, r.unit,
                                   margin[a] > room_for(travel_correction[a]) + 1e-12 ? ", widened where the pre-check met more"
                                                                              : "");
    out.summary.commanded.push_back(std::move(r));
  }

  // The residual by the module's rule: the inverse (machine file's tool length) and the tables.
  const ErrorModel model(m);
  CorrectionRule rule = [&](std::span<const double> qn, std::span<const std::int8_t> dir) {
    AppliedCorrection c;
    const auto r = solver.inverse(solver.nominal_forward(qn, m.tool.length), m.tool.length);
    c.joint.resize(n);
    for (std::size_t a = 0; a < n; ++a) c.joint[a] = r.q[a] - qn[a];
    for (const auto& t : out.reversal_tables) {
      const std::size_t a = *m.axis_index(t.axis);
      const double unit = joint_unit_factor(m.axes[a]);
      c.joint[a] += unit * interpolate_held(t.nominal, dir[a] >= 0 ? t.forward : t.reverse, qn[a] / unit);
    }
    return c;
  };
  out.summary.residual =
      residual_before_after(model, model, residual_grid(m, sampling, o.residual_points), rule, o.threads);
  out.summary.target = kKinsTarget;
  out.summary.quantity = TableQuantity::Correction;
  out.summary.sign_source =
      "kinematicsInverse returns the joints whose actual tool point (the model, e = actual - nominal) is the "
      "commanded one; the COMP_FILE type 1 columns are corrections -e added to the motor command "
      "(LinuxCNC 2.9 src/emc/motion/usrmotintf.cc usrmotLoadComp(), control.c compute_screw_comp())";
  if (!not_in_tables.empty()) {
    std::string names;
    for (const auto& s : not_in_tables) names += (names.empty() ? "" : ", ") + s;
    out.summary.warnings.push_back(
        "direction-dependent terms across an axis (" + names +
        ") are held neither by the kinematics (which has no direction of motion) nor by a joint table (which moves "
        "the joint along itself): they remain");
  }
  if (solver.rotary_count() > 0)
    out.summary.warnings.push_back(fmt::format(
        "orientation: the rotary axes correct the tool direction by damped least squares (damping {:g} rad); the "
        "rotation about the tool axis is not corrected, and near the pole (tool axis along the first rotary axis) "
        "neither is the tilt the rotary axes cannot make",
        k.solver.orientation_damping));
  return out;
}

}  // namespace mtcal
