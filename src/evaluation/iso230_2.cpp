#include "mtcal/evaluation/iso230_2.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// Sample standard deviation (n - 1); not defined for one run.
double sample_sd(const std::vector<double>& v, double m) {
  if (v.size() < 2) return kNaN;
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Range of the values over targets; NaN when any is NaN (a quantity the test does not define).
struct Range {
  double hi = -INFINITY, lo = INFINITY;
  bool undefined = false;
  void add_hi(double v) { v != v ? void(undefined = true) : void(hi = std::max(hi, v)); }
  void add_lo(double v) { v != v ? void(undefined = true) : void(lo = std::min(lo, v)); }
  void add(double v) { add_hi(v), add_lo(v); }
  double span() const { return undefined ? kNaN : hi - lo; }
};

double nan_max(double a, double b) { return a != a || b != b ? kNaN : std::max(a, b); }

}  // namespace

PositioningEvaluation evaluate_positioning(const PositioningRuns& in) {
  const std::string& source = in.source;
  const std::size_t m = in.targets.size();
  if (m < 2) throw InputError({source, 0, ""}, fmt::format("expected at least 2 targets, found {}", m));
  if (in.up.size() != m || in.down.size() != m) throw InputError({source, 0, ""}, "inconsistent run tables");
  const bool any_up = std::any_of(in.up.begin(), in.up.end(), [](const auto& v) { return !v.empty(); });
  const bool any_down = std::any_of(in.down.begin(), in.down.end(), [](const auto& v) { return !v.empty(); });
  if (!any_up && !any_down) throw InputError({source, 0, ""}, "no runs at any target");
  std::size_t n_min = std::numeric_limits<std::size_t>::max(), n_max = 0;
  for (std::size_t i = 0; i < m; ++i) {
    // A direction measured at some targets must be measured at all: a gap is lost data, not a
    // unidirectional test.
    if ((any_up && in.up[i].empty()) || (any_down && in.down[i].empty()))
      throw InputError({source, 0, ""},
                       fmt::format("target {:g} lacks runs in the {} direction, which other targets have",
                                   in.targets[i], any_up && in.up[i].empty() ? "up (+)" : "down (-)"));
    for (const auto* runs : {&in.up[i], &in.down[i]})
      if (!runs->empty()) n_min = std::min(n_min, runs->size()), n_max = std::max(n_max, runs->size());
  }

  PositioningEvaluation e;
  e.unit = in.unit;
  e.target_unit = in.target_unit.empty() ? in.unit : in.target_unit;
  e.runs = n_min;
  e.directions = any_up && any_down ? TestDirections::Both : any_up ? TestDirections::UpOnly : TestDirections::DownOnly;
  const bool both = e.directions == TestDirections::Both;
  Range a_up, a_dn, e_up, e_dn, m_range;
  double b_sum = 0;
  e.B = both ? 0.0 : kNaN;
  e.R = 0, e.R_up = any_up ? 0.0 : kNaN, e.R_down = any_down ? 0.0 : kNaN;
  for (std::size_t i = 0; i < m; ++i) {
    TargetEvaluation t;
    t.target = in.targets[i];
    std::vector<double> up, dn;  // deviations x_ij = measured - target
    for (double v : in.up[i]) up.push_back(in.deviations ? v : v - t.target);
    for (double v : in.down[i]) dn.push_back(in.deviations ? v : v - t.target);
    t.n_up = up.size();
    t.n_down = dn.size();
    t.mean_up = up.empty() ? kNaN : mean(up);  // divided by the number of runs n, not of targets
    t.mean_down = dn.empty() ? kNaN : mean(dn);
    t.mean = 0.5 * (t.mean_up + t.mean_down);
    t.reversal = t.mean_up - t.mean_down;
    t.s_up = up.empty() ? kNaN : sample_sd(up, t.mean_up);
    t.s_down = dn.empty() ? kNaN : sample_sd(dn, t.mean_down);
    t.R_up = 4 * t.s_up;
    t.R_down = 4 * t.s_down;
    t.R = both ? nan_max(2 * t.s_up + 2 * t.s_down + std::abs(t.reversal), nan_max(t.R_up, t.R_down)) : kNaN;
    if (both) {
      e.B = std::max(e.B, std::abs(t.reversal));
      b_sum += t.reversal;
      m_range.add(t.mean);
    }
    e.R = nan_max(e.R, t.R);
    if (any_up) e.R_up = nan_max(e.R_up, t.R_up), e_up.add(t.mean_up);
    if (any_down) e.R_down = nan_max(e.R_down, t.R_down), e_dn.add(t.mean_down);
    if (any_up) a_up.add_hi(t.mean_up + 2 * t.s_up), a_up.add_lo(t.mean_up - 2 * t.s_up);
    if (any_down) a_dn.add_hi(t.mean_down + 2 * t.s_down), a_dn.add_lo(t.mean_down - 2 * t.s_down);
    e.targets.push_back(t);
  }
  e.B_mean = both ? b_sum / static_cast<double>(m) : kNaN;
  e.E_up = any_up ? e_up.span() : kNaN;
  e.E_down = any_down ? e_dn.span() : kNaN;
  e.M = both ? m_range.span() : kNaN;
  e.A_up = any_up ? a_up.span() : kNaN;
  e.A_down = any_down ? a_dn.span() : kNaN;
  if (both) {
    Range ee = e_up, aa = a_up;
    ee.add_hi(e_dn.hi), ee.add_lo(e_dn.lo), ee.undefined |= e_dn.undefined;
    aa.add_hi(a_dn.hi), aa.add_lo(a_dn.lo), aa.undefined |= a_dn.undefined;
    e.E = ee.span();
    e.A = aa.span();
  } else {
    e.E = e.A = e.R = kNaN;
  }

  if (!both)
    e.notes.push_back(fmt::format(
        "unidirectional test ({} only): ISO 230-2 defines A{}, R{} and E{} for it; B, M and the bidirectional A, R, E "
        "need both directions",
        any_up ? "up (+)" : "down (-)", any_up ? "↑" : "↓", any_up ? "↑" : "↓", any_up ? "↑" : "↓"));
  if (n_min < 2)
    e.notes.push_back(
        "one run at some target: no standard deviation, so repeatability R and accuracy A are not defined "
        "(the means, B, E and M are)");
  if (n_min < 5)
    e.notes.push_back(fmt::format("ISO 230-2 asks for 5 runs per direction at each target; this test has {}", n_min));
  if (n_min != n_max)
    e.notes.push_back(
        fmt::format("the number of runs differs between targets ({} to {}); each target is "
                    "evaluated with its own",
                    n_min, n_max));
  return e;
}

PositioningRuns merge_wrapped_targets(const PositioningRuns& in, double period) {
  if (!(period > 0) || !std::isfinite(period))
    throw InputError({in.source, 0, ""}, fmt::format("expected a period > 0, found {:g}", period));
  PositioningRuns out = in;
  out.targets.clear(), out.up.clear(), out.down.clear();
  out.deviations = true;
  out.target_unit = in.target_unit.empty() ? in.unit : in.target_unit;
  const double tol = 1e-9 * period;
  auto reduce = [&](double t) {
    double r = std::fmod(t, period);
    if (r < 0) r += period;
    return r > period - tol ? 0.0 : r;
  };
  // Group by the reduced position; the representative is the target nearest zero.
  std::vector<std::size_t> group(in.targets.size());
  std::vector<double> reduced;
  std::vector<std::size_t> rep;
  for (std::size_t i = 0; i < in.targets.size(); ++i) {
    const double r = reduce(in.targets[i]);
    std::size_t g = 0;
    while (g < reduced.size() && std::abs(reduced[g] - r) > tol) ++g;
    if (g == reduced.size()) reduced.push_back(r), rep.push_back(i);
    if (std::abs(in.targets[i]) < std::abs(in.targets[rep[g]])) rep[g] = i;
    group[i] = g;
  }
  std::vector<std::size_t> order(rep.size());
  for (std::size_t g = 0; g < order.size(); ++g) order[g] = g;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return in.targets[rep[a]] < in.targets[rep[b]]; });
  for (std::size_t g : order) {
    std::vector<double> up, dn;
    std::string merged;
    for (std::size_t i = 0; i < in.targets.size(); ++i) {
      if (group[i] != g) continue;
      const double t = in.targets[i];
      for (double v : in.up[i]) up.push_back(in.deviations ? v : v - t);
      for (double v : in.down[i]) dn.push_back(in.deviations ? v : v - t);
      if (i != rep[g]) merged += fmt::format("{}{:g}", merged.empty() ? "" : ", ", t);
    }
    if (!merged.empty())
      out.warnings.push_back(
          fmt::format("targets {} and {:g} are one position of the axis (period {:g}): their runs "
                      "are pooled at {:g}",
                      merged, in.targets[rep[g]], period, in.targets[rep[g]]));
    out.targets.push_back(in.targets[rep[g]]);
    out.up.push_back(std::move(up));
    out.down.push_back(std::move(dn));
  }
  return out;
}

}  // namespace mtcal
