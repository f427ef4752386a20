#include "mtcal/io/json/planning_json.hpp"

namespace mtcal {

Json to_json(const PlanPrediction& p) {
  Json params = Json::object();
  for (const auto& e : p.parameters) {
    Json j = {{"u", number_or_null(e.u)}, {"unit", e.unit}};
    if (e.target > 0) j["target"] = e.target;
    params[e.name] = j;
  }
  return {{"poses", p.poses},         {"residuals", p.residuals}, {"unknowns", p.unknowns},
          {"rank", p.rank},           {"condition", number_or_null(p.condition)},
          {"parameters", params}};
}

Json to_json(const TimeEstimate& t) {
  return {{"total_s", t.total},         {"moves_s", t.moves},   {"probing_s", t.probing},
          {"indexing_s", t.indexing},   {"indexations", t.indexations}, {"touches", t.touches},
          {"instruments_s", t.instruments}, {"ballbar_circles", t.circles}, {"laser_lines", t.lines}};
}

Json to_json(const InstrumentSetup& s) {
  Json j = {{"id", s.id}, {"kind", feature_kind_name(s.kind)}};
  if (s.kind == ProbeFeature::Kind::Ballbar) {
    j["plane"] = s.plane;
    j["pivot"] = {s.position.x(), s.position.y(), s.position.z()};
    j["radius_mm"] = s.radius;
  } else {
    j["beam"] = {s.direction.x(), s.direction.y(), s.direction.z()};
    j["point"] = {s.position.x(), s.position.y(), s.position.z()};
    j["from_mm"] = s.from;
    j["to_mm"] = s.to;
  }
  j["rotary"] = s.rotary;
  j["readings"] = s.readings;
  j["text"] = describe_setup(s);
  return j;
}

Json to_json(const CandidateSet& c) {
  Json removed = Json::object();
  for (const auto& [name, n] : c.removed) removed[name] = n;
  return {{"considered", c.considered}, {"kept", plan_poses(c.plan)}, {"removed", removed}};
}

Json to_json(const PlanMonteCarlo& mc, const PlanPrediction& predicted) {
  Json params = Json::object();
  for (std::size_t i = 0; i < predicted.parameters.size() && i < mc.stdev.size(); ++i) {
    const double u = predicted.parameters[i].u;
    params[predicted.parameters[i].name] = {{"u_monte_carlo", mc.stdev[i]},
                                            {"ratio", number_or_null(u > 0 ? mc.stdev[i] / u : NAN)}};
  }
  Json j = {{"runs", mc.runs}, {"failed", mc.failed}, {"parameters", params}};
  if (mc.va) j["va"] = {{"mean", mc.va_mean}, {"u_monte_carlo", mc.va_stdev}};
  return j;
}

PlanReport plan_report(const PlanStudy& s) {
  PlanReport r;
  r.candidates = &s.candidates;
  r.design = &s.design;
  r.time = s.time;
  r.against = s.against;
  r.against_time = s.against_time;
  r.monte_carlo = s.monte_carlo;
  if (s.choice) r.choice = &*s.choice;
  if (s.va) {
    r.va = &*s.va;
    r.workspace = kPlanTravelWorkspace;
    r.target_va_u = s.target_va_u;
    r.against_va_u = s.against_va_u;
  }
  if (s.region) r.region = {s.region->positions, s.region->reachable, s.region->used};
  r.by_hand = s.by_hand;
  return r;
}

Json to_json(const PlanReport& r) {
  const PlanDesign& d = *r.design;
  Json j;
  j["criterion"] = d.criterion;
  j["criterion_value"] = number_or_null(d.criterion_value);
  if (r.candidates) j["candidates"] = to_json(*r.candidates);
  j["poses"] = d.poses;
  j["greedy_poses"] = d.greedy_poses;
  j["exchanges"] = d.exchanges;
  j["passes"] = d.passes;
  j["target_met"] = d.target_met;
  j["predicted"] = to_json(d.prediction);
  j["best_reachable"] = to_json(d.all_candidates);
  j["time"] = to_json(r.time);
  if (r.against) {
    Json a = {{"plan", r.against_path}, {"poses", r.against->poses}, {"predicted", to_json(*r.against)}};
    if (r.against_time) a["time"] = to_json(*r.against_time);
    a["fewer_poses_percent"] =
        r.against->poses > 0 ? 100.0 * (static_cast<double>(r.against->poses) - static_cast<double>(d.poses)) /
                                   static_cast<double>(r.against->poses)
                             : 0.0;
    j["against"] = a;
  }
  if (r.monte_carlo) {
    j["monte_carlo"] = to_json(*r.monte_carlo, d.prediction);
    if (r.monte_carlo->va && d.va_u > 0) j["monte_carlo"]["va"]["ratio"] = r.monte_carlo->va_stdev / d.va_u;
  }
  if (r.choice)
    j["parameters_chosen"] = {{"chosen", r.choice->chosen},       {"estimate", r.choice->estimate},
                              {"condition", number_or_null(r.choice->condition)},
                              {"full_rank", r.choice->full_rank}, {"examined", r.choice->examined}};
  if (r.va) {
    Json v = {{"value", r.va->va}, {"u", d.va_u}, {"u_best", d.va_u_best}};
    if (r.target_va_u > 0) v["target"] = r.target_va_u;
    if (r.against_va_u) v["u_against"] = *r.against_va_u;
    v["workspace"] = r.workspace;
    v["pairs"] = r.va->pair_lengths.size();
    j["va"] = v;
  }
  if (r.region.positions > 0)
    j["ball_region"] = {{"positions", r.region.positions}, {"reachable", r.region.reachable}, {"used", r.region.used}};
  if (!r.by_hand.empty()) {
    Json b = Json::array();
    for (const auto& s : r.by_hand) b.push_back(to_json(s));
    j["by_hand"] = b;
  }
  if (!r.out.empty()) j["out"] = r.out;
  if (!r.gcode.empty()) j["gcode"] = r.gcode;
  return j;
}

Json to_json(const LocateResult& r) {
  Json spheres = Json::array();
  for (const auto& s : r.spheres)
    spheres.push_back({{"id", s.id},
                       {"centre", {s.centre.x(), s.centre.y(), s.centre.z()}},
                       {"rough", {s.rough.x(), s.rough.y(), s.rough.z()}},
                       {"offset_mm", s.offset},
                       {"beyond", s.beyond},
                       {"ball_diameter_mm", s.ball_diameter},
                       {"contact_radius_mm", s.contact_radius},
                       {"rms_um", s.rms * 1e3},
                       {"contacts", s.contacts}});
  return Json{{"spheres", spheres}};
}

}  // namespace mtcal
