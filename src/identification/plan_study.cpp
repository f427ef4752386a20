#include "mtcal/identification/plan_study.hpp"

#include <set>

#include "mtcal/util/errors.hpp"

namespace mtcal {

PlanStudy plan_study(const Machine& m, const ProbingPlan& artefact, const std::optional<ProbingPlan>& against,
                     const PlanStudyOptions& o) {
  PlanStudy s;
  s.model = o.model;
  std::vector<ProbeFeature> features = artefact.features;
  if (o.ball_region) {
    const auto balls = region_balls(*o.ball_region, features);
    s.region = BallRegionUse{balls.size(), 0, 0};
    features.insert(features.end(), balls.begin(), balls.end());
  }
  if (features.empty() && o.instruments.ballbar_radii.empty() && o.instruments.laser_axes.empty())
    throw InputError({"artefact", 0, ""},
                     "expected the artefact's balls and facets, a region where balls may go, or ballbar circles or "
                     "laser lines");
  s.candidates = candidate_configurations(m, features, rotary_grid(m, o.rotary_step), o.reach, o.instruments);
  if (o.choose) {
    s.choice = choose_parameters(m, s.candidates.plan, *o.choose, s.model);
    s.model.estimate = s.choice->estimate;
    s.model.estimate_source = o.choose->candidates_source;
  }
  if (o.va) {
    s.workspace = o.workspace.empty() ? travel_grid(m, 5) : o.workspace;
    s.target_va_u = o.target_va_u;
    VaOptions vo = o.va_options;
    if (o.va_tie > 0)
      vo.tie_tolerance = o.va_tie;
    else if (o.target_va_u > 0)
      vo.tie_tolerance = 6 * o.target_va_u;
    s.va = va_sensitivity(m, s.workspace, s.model, vo);
  }
  if (against) {
    s.against = predict_plan(m, *against, s.model);
    // The time of its program: at its nominal targets (a plan file gives the features, not the
    // linear axes' values; predict_plan sets them too).
    s.against_time = estimate_time(m, plan_targets(m, *against), o.cycle, o.timing);
  }
  DesignOptions d;
  d.model = s.model;
  d.criterion = o.criterion;
  d.poses = o.poses;
  d.poses_source = o.poses_source;
  d.target_source = o.target_source;
  d.target_u = o.target_u;
  d.target_va_u = o.target_va_u;
  d.target_va_source = o.target_va_source;
  if (s.va) d.va_gradients = s.va->gradients;
  d.threads = o.threads;
  d.progress = o.progress;
  if (d.poses == 0 && d.target_u.empty() && d.target_va_u == 0) {
    if (!s.against)
      throw InputError({o.poses_source, 0, ""},
                       "expected a budget: a number of poses, target uncertainties, a target VA uncertainty or a plan "
                       "to do better than");
    for (const auto& e : s.against->parameters) d.target_u.emplace_back(e.name, e.u);
    d.target_source = o.against_source;
  }
  s.design = design_plan(m, s.candidates.plan, d);
  s.time = estimate_time(m, s.design.plan, o.cycle, o.timing);
  s.by_hand = instrument_setups(m, s.design.plan);
  if (s.va && s.against) s.against_va_u = va_uncertainty(*s.va, s.against->covariance);
  if (s.region) {
    std::set<std::size_t> reachable, used;
    const std::size_t first = artefact.features.size();
    const std::size_t end = features.size();  // the instruments' features come after the region's
    for (const auto& r : s.candidates.plan.records)
      if (r.feature >= first && r.feature < end) reachable.insert(r.feature);
    for (const auto& r : s.design.plan.records)
      if (r.feature >= first && r.feature < end) used.insert(r.feature);
    s.region->reachable = reachable.size();
    s.region->used = used.size();
  }
  if (o.monte_carlo > 0) {
    Machine prior = m;
    for (const auto& e : s.design.prediction.parameters) prior.set_parameter(e.name, 0.0);
    s.monte_carlo = plan_monte_carlo(m, prior, s.design.plan, s.model, o.monte_carlo, o.seed, o.threads,
                                     s.workspace);
  }
  return s;
}

}  // namespace mtcal
