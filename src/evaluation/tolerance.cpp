// Acceptance tolerances (evaluation/tolerance.hpp).
#include "mtcal/evaluation/tolerance.hpp"

#include <algorithm>
#include <cmath>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

void Tolerances::set(const std::string& quantity, double limit_um) {
  for (auto& [q, l] : limits)
    if (q == quantity) {
      l = limit_um;
      return;
    }
  limits.emplace_back(quantity, limit_um);
}

bool ToleranceVerdict::pass() const {
  return !checks.empty() && std::all_of(checks.begin(), checks.end(), [](const ToleranceCheck& c) { return c.pass; });
}

ToleranceVerdict check_tolerances(const std::vector<std::pair<std::string, double>>& values, const Tolerances& t,
                                  const std::string& where) {
  ToleranceVerdict v;
  for (const auto& entry : t.limits) {
    // Not a structured binding: clang 14 (Debian's) cannot capture one in a lambda.
    const std::string& q = entry.first;
    const double limit = entry.second;
    const auto it = std::find_if(values.begin(), values.end(), [&](const auto& kv) { return kv.first == q; });
    if (it == values.end()) {
      std::string list;
      for (const auto& kv : values) list += (list.empty() ? "" : ", ") + kv.first;
      throw InputError({where, 0, q},
                       "a tolerance for '" + printable(q) + "', which this test does not give (it gives " + list + ")");
    }
    if (!std::isfinite(it->second))
      throw InputError({where, 0, q}, "a tolerance for '" + printable(q) +
                                          "', which this test does not define (e.g. a "
                                          "unidirectional test has no reversal B)");
    if (!(limit >= 0)) throw InputError({where, 0, q}, "expected a permitted value >= 0, found a negative one");
    v.checks.push_back({q, it->second, limit, it->second <= limit});
  }
  return v;
}

std::optional<double> micrometres_per(std::string_view unit) {
  if (unit == "mm") return 1000.0;
  if (unit == "um" || unit == "µm" || unit == "micron" || unit == "microns") return 1.0;
  if (unit == "nm") return 1e-3;
  if (unit == "m") return 1e6;
  if (unit == "in" || unit == "inch") return 25400.0;
  return std::nullopt;
}

std::vector<std::pair<std::string, double>> tolerance_values(const PositioningEvaluation& e) {
  const auto k = micrometres_per(e.unit);
  if (!k)
    throw InputError({e.unit, 0, ""}, "tolerances are in µm; the measurements' unit '" + e.unit +
                                          "' is not a known length unit (mm, um, nm, m, in)");
  return {{"A", e.A * *k}, {"E", e.E * *k}, {"M", e.M * *k}, {"R", e.R * *k}, {"B", e.B * *k}};
}

std::vector<std::pair<std::string, double>> tolerance_values(const BallbarEvaluation& e) {
  std::vector<std::pair<std::string, double>> values;
  if (e.G_b)
    values.emplace_back("G", *e.G_b * 1e3);
  else if (e.cw || e.ccw)
    values.emplace_back("G", (e.cw ? e.cw->G : e.ccw->G) * 1e3);
  values.emplace_back("F", std::max(std::abs(e.F_max), std::abs(e.F_min)) * 1e3);
  if (e.H) values.emplace_back("H", *e.H * 1e3);
  return values;
}

}  // namespace mtcal
