#include "mtcal/prediction/prediction_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {

const ErrorComponent* PredictionModel::find(const std::string& n) const {
  for (const auto& c : components)
    if (c.name == n) return &c;
  return nullptr;
}

std::vector<std::string> PredictionModel::variables() const {
  std::set<std::string> s;
  for (const auto& c : components) {
    if (!c.variable.empty()) s.insert(c.variable);
    if (!c.stages.empty()) s.insert(c.speed_variable);
    if (c.ramp) s.insert(c.ramp->variable);
    if (!c.times.empty()) s.insert(c.times);
  }
  return {s.begin(), s.end()};
}

double evaluate_stages(const std::vector<SpeedStage>& s, double speed, double x) {
  if (s.empty() || !(speed > 0.0) || !std::isfinite(speed)) return std::numeric_limits<double>::quiet_NaN();
  // Eq. 3.9 / 5.19 and 3.10 / 5.20: proportional scaling of the nearest stage outside the range.
  if (speed <= s.front().speed) return speed / s.front().speed * s.front().model(x);
  if (speed >= s.back().speed) return speed / s.back().speed * s.back().model(x);
  std::size_t k = 1;
  while (s[k].speed < speed) ++k;
  const auto& lo = s[k - 1];
  const auto& hi = s[k];
  // Eq. 3.7-3.8 / 5.17-5.18 with each stage weighted by its nearness (see the header).
  const double w = (speed - lo.speed) / (hi.speed - lo.speed);
  return (1.0 - w) * lo.model(x) + w * hi.model(x);
}

namespace {

// The model's own value of component i (before scale, ramp and times). raw_before: the values of
// the earlier components when the caller has them (predict_point), else an 'of' is evaluated.
double component_raw(const PredictionModel& m, std::size_t i, const std::function<double(const std::string&)>& lookup,
                     bool strict, const std::string& where, std::vector<std::string>& warnings,
                     const std::vector<double>* raw_before) {
  const ErrorComponent& c = m.components[i];
  if (!c.of.empty()) {
    const auto it =
        std::find_if(m.components.begin(), m.components.end(), [&](const ErrorComponent& o) { return o.name == c.of; });
    const auto k = static_cast<std::size_t>(it - m.components.begin());
    return raw_before ? (*raw_before)[k] : component_raw(m, k, lookup, strict, where, warnings, nullptr);
  }
  const double x = lookup(c.variable);
  if (c.valid && (x < c.valid->first || x > c.valid->second)) {
    const std::string msg =
        fmt::format("{}: {} = {:g} is outside the validity range [{:g}, {:g}] of the model ({})", c.name, c.variable, x,
                    c.valid->first, c.valid->second, strict ? "refused: strict validity" : "extrapolated");
    if (strict) throw InputError({where, 0, c.variable}, msg);
    warnings.push_back(msg);
  }
  double raw = 0.0;
  if (c.model) {
    raw = (*c.model)(x);
  } else {
    // The stage interpolation and the proportional scaling (eq. 3.7-3.10) are in S / S_stage:
    // a spindle at rest or a negative speed has no thermal stage.
    const double speed = lookup(c.speed_variable);
    if (!(speed > 0.0) || !std::isfinite(speed))
      throw InputError(
          {where, 0, c.speed_variable},
          fmt::format("{}: expected a spindle speed {} > 0 rpm for the speed stages (eq. 3.7-3.10), found {:g}", c.name,
                      c.speed_variable, speed));
    raw = evaluate_stages(c.stages, speed, x);
  }
  if (!std::isfinite(raw))
    throw InputError({where, 0, c.variable}, fmt::format("{}: the model is undefined at {} = {:g} (line {} of {})",
                                                         c.name, c.variable, x, c.line, m.file));
  return raw;
}

double scaled(const ErrorComponent& c, double raw, const std::function<double(const std::string&)>& lookup) {
  double v = c.scale * raw;
  if (c.ramp) v *= (lookup(c.ramp->variable) - c.ramp->zero_at) / (c.ramp->one_at - c.ramp->zero_at);
  if (!c.times.empty()) v *= lookup(c.times);
  return v;
}

}  // namespace

ComponentValue evaluate_component(const PredictionModel& m, const std::string& name,
                                  const std::function<double(const std::string&)>& lookup, bool strict,
                                  const std::string& where) {
  const ErrorComponent* c = m.find(name);
  if (!c) throw InputError({m.file, 0, name}, "the model has no component '" + printable(name) + "'");
  ComponentValue v;
  v.raw =
      component_raw(m, static_cast<std::size_t>(c - m.components.data()), lookup, strict, where, v.warnings, nullptr);
  v.value = scaled(*c, v.raw, lookup);
  return v;
}

PointPrediction predict_point(const PredictionModel& m, const std::function<double(const std::string&)>& lookup,
                              bool strict, const std::string& where) {
  PointPrediction p;
  p.values.reserve(m.components.size());
  for (std::size_t i = 0; i < m.components.size(); ++i) {
    const ErrorComponent& c = m.components[i];
    const double raw = component_raw(m, i, lookup, strict, where, p.warnings, &p.raw);
    const double v = scaled(c, raw, lookup);
    p.raw.push_back(raw);
    p.values.push_back(v);
    if (c.axis) p.e[c.axis - 'x'] += v;
  }
  return p;
}

}  // namespace mtcal

namespace mtcal {

int PredictionPoints::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> components_reading(const PredictionModel& m, const std::string& v) {
  std::vector<std::string> users;
  for (const auto& c : m.components)
    if (c.variable == v || c.times == v || (c.ramp && c.ramp->variable == v) ||
        (!c.stages.empty() && c.speed_variable == v))
      users.push_back(c.name);
  return users;
}

std::vector<std::string> missing_variables(const PredictionModel& m, const PredictionPoints& points,
                                           const std::map<std::string, double>& constants) {
  std::vector<std::string> out;
  for (const auto& v : m.variables())
    if (points.column(v) < 0 && !constants.count(v)) out.push_back(v);
  return out;
}

std::vector<CompensationOffset> compensation_offsets(const PredictionPoints& points,
                                                     const std::vector<PointPrediction>& predictions) {
  const int step_col = points.column("step");
  if (step_col < 0)
    throw InputError({points.source, 0, "step"}, "compensation offsets per step need a 'step' column in the points");
  std::vector<std::pair<double, std::array<double, 4>>> sums;  // step, sum x y z, count
  for (std::size_t r = 0; r < points.rows.size() && r < predictions.size(); ++r) {
    const double s = points.rows[r][static_cast<std::size_t>(step_col)];
    auto it = std::find_if(sums.begin(), sums.end(), [&](const auto& c) { return c.first == s; });
    if (it == sums.end()) it = sums.insert(sums.end(), {s, {0, 0, 0, 0}});
    for (int a = 0; a < 3; ++a) it->second[static_cast<std::size_t>(a)] += predictions[r].e[a];
    it->second[3] += 1;
  }
  std::vector<CompensationOffset> out;
  for (const auto& [s, v] : sums) out.push_back({s, {-v[0] / v[3], -v[1] / v[3], -v[2] / v[3]}});
  return out;
}

PredictionRun predict_points(const PredictionModel& m, const PredictionPoints& points,
                             const std::map<std::string, double>& constants, bool strict, bool compensation) {
  // Every variable the model reads must be a column or a constant: checked before any work.
  for (const auto& v : missing_variables(m, points, constants)) {
    std::string users;
    for (const auto& u : components_reading(m, v)) users += (users.empty() ? "" : ", ") + u;
    throw InputError({points.source, 0, v},
                     fmt::format("missing column '{}' needed by {} (give it as a column or as a constant)", v, users));
  }
  PredictionRun run;
  run.points = points;
  for (std::size_t r = 0; r < points.rows.size(); ++r) {
    auto lookup = [&](const std::string& name) {
      const int c = points.column(name);
      return c >= 0 ? points.rows[r][static_cast<std::size_t>(c)] : constants.at(name);
    };
    run.predictions.push_back(predict_point(m, lookup, strict, fmt::format("{}:{}", points.source, points.lines[r])));
    for (const auto& w : run.predictions.back().warnings)
      run.warnings.push_back(fmt::format("line {}: {}", points.lines[r], w));
  }
  if (compensation) run.compensation = compensation_offsets(points, run.predictions);
  return run;
}

}  // namespace mtcal
