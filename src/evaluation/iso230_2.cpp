#include "mtcal/evaluation/iso230_2.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double sample_sd(const std::vector<double>& v, double m) {
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

}  // namespace

PositioningEvaluation evaluate_positioning(const PositioningRuns& in) {
  const std::string& source = in.source;
  const std::size_t m = in.targets.size();
  if (m < 2) throw InputError({source, 0, ""}, fmt::format("expected at least 2 targets, found {}", m));
  if (in.up.size() != m || in.down.size() != m) throw InputError({source, 0, ""}, "inconsistent run tables");
  const std::size_t n = in.up[0].size();
  for (std::size_t i = 0; i < m; ++i) {
    if (in.up[i].empty() || in.down[i].empty())
      throw InputError({source, 0, ""}, fmt::format("target {:g} lacks runs in the {} direction (ISO 230-2 needs both)",
                                                    in.targets[i], in.up[i].empty() ? "up (+)" : "down (-)"));
    if (in.up[i].size() != n || in.down[i].size() != n)
      throw InputError({source, 0, ""},
                       fmt::format("unequal run counts: target {:g} has {} up and {} down runs, "
                                   "target {:g} has {} up",
                                   in.targets[i], in.up[i].size(), in.down[i].size(), in.targets[0], n));
  }
  if (n < 2) throw InputError({source, 0, ""}, fmt::format("expected at least 2 runs per direction, found {}", n));

  PositioningEvaluation e;
  e.unit = in.unit;
  e.runs = n;
  double a_hi_up = -INFINITY, a_lo_up = INFINITY, a_hi_dn = -INFINITY, a_lo_dn = INFINITY;
  double e_hi_up = -INFINITY, e_lo_up = INFINITY, e_hi_dn = -INFINITY, e_lo_dn = INFINITY;
  double m_hi = -INFINITY, m_lo = INFINITY, b_sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    TargetEvaluation t;
    t.target = in.targets[i];
    std::vector<double> up, dn;  // deviations x_ij = measured - target
    for (double v : in.up[i]) up.push_back(v - t.target);
    for (double v : in.down[i]) dn.push_back(v - t.target);
    t.mean_up = mean(up);  // divided by the number of runs n, not of targets
    t.mean_down = mean(dn);
    t.mean = 0.5 * (t.mean_up + t.mean_down);
    t.reversal = t.mean_up - t.mean_down;
    t.s_up = sample_sd(up, t.mean_up);
    t.s_down = sample_sd(dn, t.mean_down);
    t.R_up = 4 * t.s_up;
    t.R_down = 4 * t.s_down;
    t.R = std::max({2 * t.s_up + 2 * t.s_down + std::abs(t.reversal), t.R_up, t.R_down});
    e.B = std::max(e.B, std::abs(t.reversal));
    b_sum += t.reversal;
    e.R = std::max(e.R, t.R);
    e.R_up = std::max(e.R_up, t.R_up);
    e.R_down = std::max(e.R_down, t.R_down);
    e_hi_up = std::max(e_hi_up, t.mean_up), e_lo_up = std::min(e_lo_up, t.mean_up);
    e_hi_dn = std::max(e_hi_dn, t.mean_down), e_lo_dn = std::min(e_lo_dn, t.mean_down);
    m_hi = std::max(m_hi, t.mean), m_lo = std::min(m_lo, t.mean);
    a_hi_up = std::max(a_hi_up, t.mean_up + 2 * t.s_up), a_lo_up = std::min(a_lo_up, t.mean_up - 2 * t.s_up);
    a_hi_dn = std::max(a_hi_dn, t.mean_down + 2 * t.s_down), a_lo_dn = std::min(a_lo_dn, t.mean_down - 2 * t.s_down);
    // Values near the floating-point range (1e308) overflow the sums: an error, not inf results.
    for (double v :
         {t.mean_up, t.mean_down, t.mean, t.reversal, t.s_up, t.s_down, t.R, a_hi_up, a_lo_up, a_hi_dn, a_lo_dn})
      if (!std::isfinite(v))
        throw InputError({source, 0, ""}, fmt::format("the deviations at target {:g} overflow (found values beyond "
                                                      "the floating-point range); expected measured positions",
                                                      t.target));
    e.targets.push_back(t);
  }
  e.B_mean = b_sum / static_cast<double>(m);
  e.E_up = e_hi_up - e_lo_up;
  e.E_down = e_hi_dn - e_lo_dn;
  e.E = std::max(e_hi_up, e_hi_dn) - std::min(e_lo_up, e_lo_dn);
  e.M = m_hi - m_lo;
  e.A_up = a_hi_up - a_lo_up;
  e.A_down = a_hi_dn - a_lo_dn;
  e.A = std::max(a_hi_up, a_hi_dn) - std::min(a_lo_up, a_lo_dn);
  for (double v : {e.B_mean, e.E, e.E_up, e.E_down, e.M, e.A, e.A_up, e.A_down})
    if (!std::isfinite(v))
      throw InputError({source, 0, ""},
                       "the ranges over the targets overflow (found values beyond the floating-point "
                       "range); expected measured positions");
  return e;
}

}  // namespace mtcal
