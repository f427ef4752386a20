#include "mtcal/compensation/compensation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/request_error.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal {

const char* to_string(TableQuantity q) {
  switch (q) {
    case TableQuantity::Error: return "error";
    case TableQuantity::Correction: return "correction";
    case TableQuantity::ActualPosition: return "actual position";
  }
  return "?";
}

double interpolate_held(std::span<const double> positions, std::span<const double> values, double x) {
  if (positions.empty() || positions.size() != values.size())
    throw ModelError("interpolate_held: expected as many values as positions (at least one)");
  if (x <= positions.front()) return values.front();
  if (x >= positions.back()) return values.back();
  const auto it = std::upper_bound(positions.begin(), positions.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - positions.begin());  // positions[i-1] <= x < positions[i]
  const double t = (x - positions[i - 1]) / (positions[i] - positions[i - 1]);
  return values[i - 1] + t * (values[i] - values[i - 1]);
}

double ControllerTable::value_at(double q, std::int8_t dir) const {
  double p = q / unit;
  if (wrap_turn) p -= 360.0 * std::floor(p / 360.0);
  const std::vector<double>& column = dir < 0 && !reverse.empty() ? reverse : forward;
  return sign * interpolate_held(position, column, p) * unit;
}

CorrectionRule table_rule(std::vector<ControllerTable> tables, std::size_t joints) {
  for (const auto& t : tables)
    if (t.input >= joints || t.output >= joints)
      throw ModelError("table_rule: a table's joint is not one of the machine's " + std::to_string(joints));
  return [tables = std::move(tables), joints](std::span<const double> q, std::span<const std::int8_t> dir) {
    AppliedCorrection c;
    c.joint.assign(joints, 0.0);
    for (const auto& t : tables) c.joint[t.output] += t.value_at(q[t.input], dir[t.input]);
    return c;
  };
}

ResidualSummary predict_residual(const ErrorModel& model, const std::vector<std::vector<double>>& axis_values,
                                 const CorrectionRule& rule, int threads) {
  const std::size_t n = model.axis_count();
  if (axis_values.size() != n)
    throw ModelError("predict_residual: expected joint values for each of the " + std::to_string(n) + " axes");
  std::size_t count = 1;
  for (const auto& v : axis_values) {
    if (v.empty()) throw ModelError("predict_residual: an axis has no joint value");
    count *= v.size();
  }
  // Two error vectors per configuration (forward, reverse), before and after.
  std::vector<Vec3> before(2 * count), after(2 * count);
  const std::size_t chunk = 256;
  parallel_for((count + chunk - 1) / chunk, threads, [&](std::size_t chunk_index, std::size_t) {
    std::vector<double> q(n), qc(n);
    std::vector<std::int8_t> dir(n);
    for (std::size_t k = chunk_index * chunk; k < std::min(count, (chunk_index + 1) * chunk); ++k) {
      // Mixed radix, the last axis of the chain fastest (as grid_error_map orders it).
      std::size_t rest = k;
      for (std::size_t a = n; a-- > 0;) {
        q[a] = axis_values[a][rest % axis_values[a].size()];
        rest /= axis_values[a].size();
      }
      const Affine nominal = model.nominal_pose(q);
      for (int d = 0; d < 2; ++d) {
        std::fill(dir.begin(), dir.end(), static_cast<std::int8_t>(d == 0 ? 1 : -1));
        before[2 * k + d] = model.evaluate(q, dir).translation;
        const AppliedCorrection c = rule(q, dir);
        qc = q;
        for (std::size_t a = 0; a < c.joint.size() && a < n; ++a) qc[a] += c.joint[a];
        after[2 * k + d] = volumetric_error(model.actual_pose(qc, dir), nominal).translation + c.cartesian;
      }
    }
  });
  ResidualSummary s;
  s.configurations = count;
  for (std::size_t i = 0; i < before.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      s.max_before[a] = std::max(s.max_before[a], std::abs(before[i][a]));
      s.max_after[a] = std::max(s.max_after[a], std::abs(after[i][a]));
      s.max_norm_before = std::max(s.max_norm_before, before[i].norm());
      s.max_norm_after = std::max(s.max_norm_after, after[i].norm());
    }
  s.va_before = volumetric_accuracy(before).va.value;
  s.va_after = volumetric_accuracy(after).va.value;
  return s;
}

std::vector<AxisSampling> resolve_sampling(const Machine& m, const CompensationOptions& o, std::size_t default_points,
                                           std::size_t max_points, const std::string& target) {
  for (const auto& s : o.sampling)
    if (!m.axis_index(s.axis))
      throw InputError({target, 0, std::string(1, s.axis)},
                       fmt::format("expected an axis of {}, found {}", m.topology.chain, s.axis));
  std::vector<AxisSampling> out;
  for (const auto& ax : m.axes) {
    const auto given =
        std::find_if(o.sampling.begin(), o.sampling.end(), [&](const AxisSampling& s) { return s.axis == ax.letter; });
    const std::size_t points = o.points ? o.points : default_points;
    AxisSampling s = given != o.sampling.end() ? *given : default_sampling(m, ax.letter, points);
    if (s.points == 0) s.points = points;
    if (s.points > max_points)
      throw RequestError({target, 0, std::string(1, ax.letter)},
                         fmt::format("expected at most {} positions per table (the controller's limit), found {}",
                                     max_points, s.points),
                         {"points"});
    sample_positions(s, target);  // checks the range and the count
    if (ax.travel) {
      const double lo = to_user_units(ax, ax.travel->min), hi = to_user_units(ax, ax.travel->max);
      const double slack = 1e-9 * std::max(1.0, hi - lo);
      if (s.start < lo - slack || s.end > hi + slack)
        throw InputError({target, 0, std::string(1, ax.letter)},
                         fmt::format("expected a range within the travel [{:g}, {:g}] {} of {}, found [{:g}, {:g}]", lo,
                                     hi, joint_unit_name(ax), ax.letter, s.start, s.end));
    }
    out.push_back(s);
  }
  return out;
}

std::vector<std::vector<double>> residual_grid(const Machine& m, const std::vector<AxisSampling>& sampling,
                                               std::size_t points_per_axis) {
  std::vector<std::vector<double>> grid;
  for (std::size_t a = 0; a < m.axes.size(); ++a) {
    AxisSampling s = sampling[a];
    s.points = std::max<std::size_t>(2, points_per_axis);
    std::vector<double> v = sample_positions(s, "residual grid");
    for (double& x : v) x *= joint_unit_factor(m.axes[a]);
    grid.push_back(std::move(v));
  }
  return grid;
}

std::vector<NotCompensated> errors_not_held(const Machine& m, const std::vector<std::vector<double>>& grid,
                                            const std::function<bool(const ErrorName&)>& held, int threads) {
  std::vector<ErrorName> names;
  for (const auto& p : m.parameters())
    if (p.value != 0.0 && !held(p.error) && std::find(names.begin(), names.end(), p.error) == names.end())
      names.push_back(p.error);
  std::vector<NotCompensated> out;
  for (const auto& name : names) {
    Machine only = m;
    only.keep_only({name.str()});
    const ErrorModel model(only);
    const auto r = predict_residual(
        model, grid, [](auto, auto) { return AppliedCorrection{}; }, threads);
    out.push_back({name.str(), r.max_norm_before, "mm"});
  }
  return out;
}

Machine linear_axis_errors(const Machine& m) {
  Machine out = m;
  const auto params = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i) {
    const ErrorName& n = params[i].error;
    const auto a = n.kind == ErrorKind::Mounting ? std::nullopt : m.axis_index(n.body);
    if (params[i].value != 0.0 && (!a || m.axes[*a].kind != AxisKind::Linear)) out.set_parameter(i, 0.0);
  }
  return out;
}

std::vector<PositioningTable> positioning_tables(const ErrorModel& model, const std::vector<AxisSampling>& sampling,
                                                 std::span<const double> reference, const std::string& where) {
  const Machine& m = model.machine();
  std::vector<PositioningTable> out;
  for (std::size_t a = 0; a < m.axes.size(); ++a) {
    const Axis& ax = m.axes[a];
    if (ax.kind != AxisKind::Linear) continue;
    const JointErrorTable t = sample_joint_error(model, sampling[a], reference, where);
    PositioningTable table{ax.letter, t.position, {}, {}};
    bool any = false;
    for (std::size_t i = 0; i < t.position.size(); ++i) {
      table.forward.push_back(t.forward[i].translation.dot(ax.direction()));
      table.reverse.push_back(t.reverse[i].translation.dot(ax.direction()));
      any = any || table.forward.back() != 0.0 || table.reverse.back() != 0.0;
    }
    if (any) out.push_back(std::move(table));
  }
  return out;
}

ResidualSummary residual_before_after(const ErrorModel& machine, const ErrorModel& compensated,
                                      const std::vector<std::vector<double>>& grid, const CorrectionRule& rule,
                                      int threads) {
  ResidualSummary r = predict_residual(
      machine, grid, [](auto, auto) { return AppliedCorrection{}; }, threads);
  const ResidualSummary after = predict_residual(compensated, grid, rule, threads);
  r.max_after = after.max_after;
  r.max_norm_after = after.max_norm_after;
  r.va_after = after.va_after;
  return r;
}

}  // namespace mtcal
