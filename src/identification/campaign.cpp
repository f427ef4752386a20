#include "mtcal/identification/campaign.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

DeviationSummary summarise(const std::vector<ProbedDeviation>& probed, bool after) {
  DeviationSummary s;
  s.count = probed.size();
  double sum2 = 0.0;
  for (std::size_t i = 0; i < probed.size(); ++i) {
    const double n = (after ? probed[i].after : probed[i].before).norm();
    if (n > s.max) s.max = n, s.max_index = i;
    sum2 += n * n;
  }
  s.rms = probed.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(probed.size()));
  s.rms_coordinate = s.rms / std::sqrt(3.0);
  return s;
}

}  // namespace

CampaignResult campaign_report(const Machine& machine, const ProbingPlan& before, const ProbingPlan& after,
                               const IdentifiedSummary* identified, const Machine* truth,
                               const PoseCheck* poses_before, const PoseCheck* poses_after,
                               const CampaignOptions& o) {
  if (!before.measured) throw InputError({o.before_source, 0, ""}, "expected a measurement (readings X, Y, Z), found a plan");
  if (!after.measured) throw InputError({o.after_source, 0, ""}, "expected a measurement (readings X, Y, Z), found a plan");
  if (before.records.size() != after.records.size())
    throw InputError({o.after_source, 0, ""},
                     fmt::format("expected the {} records of {} (the same plan measured again), found {}",
                                 before.records.size(), o.before_source, after.records.size()));
  if (o.reference == BallReference::Identified && !identified)
    throw InputError({o.before_source, 0, ""}, "expected an identification to take the identified ball centres from");
  Machine nominal_machine = machine;
  nominal_machine.clear_errors();
  const ErrorModel nominal(nominal_machine);
  CampaignResult r;
  r.reference = o.reference;
  r.probing_noise = o.probing_noise;
  for (std::size_t i = 0; i < before.records.size(); ++i) {
    const ProbingRecord& b = before.records[i];
    const ProbingRecord& a = after.records[i];
    const ProbeFeature& fb = before.features[b.feature];
    const ProbeFeature& fa = after.features[a.feature];
    bool same = fb.id == fa.id && fb.kind == fa.kind && b.indexation == a.indexation && b.q.size() == a.q.size();
    for (std::size_t k = 0; same && k < b.q.size(); ++k)
      if (machine.axes[k].kind == AxisKind::Rotary && std::abs(b.q[k] - a.q[k]) > 1e-9) same = false;
    if (!same)
      throw InputError({o.after_source, a.line, ""},
                       fmt::format("expected the record of {} line {} (feature {}, indexation {}), found feature {}, "
                                   "indexation {} or other rotary values: not the same plan",
                                   o.before_source, b.line, fb.id, b.indexation, fa.id, a.indexation));
    if (fb.kind != ProbeFeature::Kind::Ball) {
      ++r.facets;
      continue;
    }
    Vec3 centre = fb.position;
    if (o.reference == BallReference::Identified) {
      const auto it = identified->balls.find(fb.id);
      if (it == identified->balls.end())
        throw InputError({identified->source, 0, "artefact.balls"},
                         fmt::format("expected the estimated centre of ball {}, found none", fb.id));
      centre = it->second;
    }
    ProbedDeviation d;
    d.record = i;
    d.indexation = b.indexation;
    d.feature = fb.id;
    for (std::size_t k = 0; k < b.q.size(); ++k)
      if (machine.axes[k].kind == AxisKind::Rotary) d.rotary.push_back(b.q[k]);
    d.line_before = b.line;
    d.line_after = a.line;
    d.before = nominal.nominal_pose(b.q).t - centre;
    d.after = nominal.nominal_pose(a.q).t - centre;
    if (!d.before.allFinite() || !d.after.allFinite())
      throw Error(fmt::format("{}:{}: a non-finite probed centre", o.before_source, b.line));
    r.probed.push_back(std::move(d));
  }
  if (r.probed.empty())
    throw InputError({o.before_source, 0, ""}, "expected ball records (sphere centres) to compare, found none");
  if (o.reference == BallReference::Mean) {
    // Each ball's deviations about their mean, before and after separately.
    std::map<std::string, std::pair<Vec3, Vec3>> sum;
    std::map<std::string, double> count;
    for (const auto& d : r.probed) {
      auto& [b, a] = sum.try_emplace(d.feature, Vec3::Zero(), Vec3::Zero()).first->second;
      b += d.before;
      a += d.after;
      count[d.feature] += 1;
    }
    for (auto& d : r.probed) {
      const auto& [b, a] = sum[d.feature];
      d.before -= b / count[d.feature];
      d.after -= a / count[d.feature];
    }
  }
  r.before = summarise(r.probed, false);
  r.after = summarise(r.probed, true);
  if (o.probing_noise > 0) r.residual_goal = r.after.rms_coordinate <= 2 * o.probing_noise;

  if (identified) r.identification = *identified;
  if (identified && truth) {
    for (const auto& p : identified->parameters) {
      ParameterCheck c{p.name, p.unit, p.value, p.u, std::nullopt, 0.0, std::numeric_limits<double>::quiet_NaN()};
      if (const auto i = truth->parameter_index(p.name)) {
        c.truth = truth->parameter(*i);
        c.deviation = p.value - *c.truth;
        if (std::isfinite(p.u) && p.u > 0) c.ratio = std::abs(c.deviation) / p.u;
      }
      if (std::isfinite(c.ratio)) {
        r.max_ratio = std::max(r.max_ratio, c.ratio);
        if (c.ratio > 3) ++r.beyond_3u;
      }
      r.parameters.push_back(c);
    }
    for (const auto& p : truth->parameters()) {
      if (p.value == 0.0) continue;
      const bool estimated = std::any_of(identified->parameters.begin(), identified->parameters.end(),
                                         [&](const EstimatedParameter& e) { return e.name == p.name; });
      if (!estimated) r.not_estimated.emplace_back(p.name, p.value);
    }
    const bool all_known = std::all_of(r.parameters.begin(), r.parameters.end(),
                                       [](const ParameterCheck& c) { return c.truth && std::isfinite(c.ratio); });
    r.parameter_goal = all_known && r.beyond_3u == 0 && !r.parameters.empty();
  }
  if (poses_before) r.poses_before = *poses_before;
  if (poses_after) r.poses_after = *poses_after;
  return r;
}

}  // namespace mtcal
