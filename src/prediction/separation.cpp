#include "mtcal/prediction/separation.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
std::vector<PositionStep> separate_position(const std::vector<PositionObservation>& observations) {
  std::vector<PositionStep> out;
  auto slot = [&](int step, char ax) -> PositionStep& {
    for (auto& p : out)
      if (p.step == step && p.axis == ax) return p;
    out.push_back({step, ax, std::nan(""), 0.0, 0});
    return out.back();
  };
  for (const auto& o : observations) {
    PositionStep& p = slot(o.step, o.axis);
    p.e_pos += o.cmm - o.probe;
    ++p.count;
    if (std::isnan(p.distance)) p.distance = o.distance;
  }
  for (auto& p : out) p.e_pos /= p.count;
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.axis != b.axis ? a.axis < b.axis : a.step < b.step; });
  return out;
}

std::vector<ControlStep> separate_control(const std::vector<DimensionRecord>& records, const std::string& a,
                                          const std::string& b, const std::string& source,
                                          const std::map<std::pair<int, char>, double>& subtract) {
  std::vector<ControlStep> out;
  auto components = [&](const DimensionRecord& d) {
    for (const auto* c : {&d.e_pf, &d.e_pt, &d.e_pos})
      if (!c->has_value())
        throw InputError({source, d.line,
                          c == &d.e_pf   ? "e_pf"
                          : c == &d.e_pt ? "e_pt"
                                         : "e_pos"},
                         fmt::format("{} step {} {} is compared (eq. 3.11-3.15) but this component is empty",
                                     d.workpiece, d.step, d.axis));
  };
  bool any_a = false, any_b = false;
  for (const auto& ra : records) {
    any_a |= ra.workpiece == a;
    any_b |= ra.workpiece == b;
    if (ra.workpiece != a) continue;
    const auto rb = std::find_if(records.begin(), records.end(), [&](const auto& o) {
      return o.workpiece == b && o.step == ra.step && o.axis == ra.axis;
    });
    if (rb == records.end()) continue;
    components(ra);
    components(*rb);
    ControlStep c{ra.step, ra.axis, ra.nominal, 0.0};
    c.value = ((ra.measured - ra.nominal) - (rb->measured - rb->nominal)) - (*ra.e_pf - *rb->e_pf) -
              (*ra.e_pt - *rb->e_pt) - (*ra.e_pos - *rb->e_pos);
    if (!subtract.empty()) {
      const auto it = subtract.find({ra.step, ra.axis});
      if (it == subtract.end())
        throw InputError({source, ra.line, "step"},
                         fmt::format("no e_ctrl(2400-100) for step {} {} to subtract (eq. 3.15)", ra.step, ra.axis));
      c.value -= it->second;
    }
    out.push_back(c);
  }
  if (!any_a || !any_b)
    throw InputError({source, 0, "workpiece"}, fmt::format("workpiece '{}' is not in the table", any_a ? b : a));
  if (out.empty()) throw InputError({source, 0, "step"}, fmt::format("{} and {} share no step and axis", a, b));
  std::sort(out.begin(), out.end(),
            [](const auto& x, const auto& y) { return x.axis != y.axis ? x.axis < y.axis : x.step < y.step; });
  return out;
}

}  // namespace mtcal

namespace mtcal {

PositionSeparation separate_position_with_fits(const std::vector<PositionObservation>& observations) {
  PositionSeparation out;
  out.steps = separate_position(observations);
  for (char ax : {'X', 'Y', 'Z'}) {
    std::vector<double> d, e;
    for (const auto& s : out.steps)
      if (s.axis == ax) {
        d.push_back(s.distance);
        e.push_back(s.e_pos);
      }
    const ModelSpec spec =
        ax == 'Z' ? ModelSpec{ModelForm::Polynomial, 1, std::nullopt} : ModelSpec{ModelForm::Polynomial, 2, 0.0};
    if (d.size() < 3) continue;
    out.fits.emplace_back(std::string("e_pos_") + static_cast<char>(std::tolower(ax)), fit_model(spec, d, e));
  }
  return out;
}

std::map<std::pair<int, char>, double> control_model_errors(const PredictionModel& m,
                                                            const std::vector<DimensionRecord>& records,
                                                            const std::string& a, const std::string& source,
                                                            std::vector<std::string>& warnings) {
  std::map<std::pair<int, char>, double> sub;
  for (const auto& r : records) {
    if (r.workpiece != a) continue;
    const std::string name = r.axis == 'X' ? "e_ctrl_x" : "e_ctrl_y";
    const ErrorComponent* c = m.find(name);
    if (!c) throw InputError({m.file, 0, name}, "the model has no component '" + printable(name) + "' (eq. 5.52-5.53)");
    const auto lookup = [&](const std::string& v) -> double {
      if (v == c->variable) return r.nominal;
      if (c->ramp && v == c->ramp->variable) return c->ramp->one_at;
      throw InputError({m.file, c->line, v},
                       fmt::format("{} reads '{}': separate control gives only its distance ({}) and its feed ramp",
                                   name, v, c->variable));
    };
    const ComponentValue v = evaluate_component(m, name, lookup, false, fmt::format("{}:{}", source, r.line));
    for (const auto& w : v.warnings) warnings.push_back(fmt::format("line {}: {}", r.line, w));
    sub[{r.step, r.axis}] = v.value;
  }
  return sub;
}

ControlSeparation separate_control(const std::vector<DimensionRecord>& records, const std::string& a,
                                   const std::string& b, const std::string& source, const PredictionModel* model) {
  ControlSeparation out;
  out.a = a;
  out.b = b;
  out.quantity = model ? "e_cpr" : "e_ctrl";
  std::map<std::pair<int, char>, double> sub;
  if (model) sub = control_model_errors(*model, records, a, source, out.warnings);
  out.steps = separate_control(records, a, b, source, sub);
  return out;
}

}  // namespace mtcal
