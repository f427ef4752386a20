#include "mtcal/io/json/campaign_json.hpp"

#include <cmath>

#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json um3(const Vec3& v) { return Json::array({v.x() * 1e3, v.y() * 1e3, v.z() * 1e3}); }

Json summary(const DeviationSummary& s, const std::vector<ProbedDeviation>& probed) {
  return {{"count", s.count},
          {"max_um", s.max * 1e3},
          {"rms_um", s.rms * 1e3},
          {"rms_coordinate_um", s.rms_coordinate * 1e3},
          {"max_record", probed.empty() ? Json(nullptr) : Json(probed[s.max_index].record)}};
}

Json pose_summary(const PoseCheck& c) {
  return {{"poses", c.poses.size()},
          {"tool_length", c.tool_length},
          {"max_um", c.max_error * 1e3},
          {"max_pose", c.max_index},
          {"rms_um", c.rms_error * 1e3},
          {"va_um", c.va.va.value * 1e3},
          {"va_pair", Json::array({c.va.va.i, c.va.va.j})},
          {"max_direction_urad", c.max_direction_error * 1e6}};
}

}  // namespace

Json to_json(const ErrorDraw& draw) {
  Json drawn = Json::array();
  for (const auto& e : draw.drawn)
    drawn.push_back({{"error", e.error.str()},
                     {"size", e.rotational ? e.size * 1e6 : e.size * 1e3},
                     {"unit", e.rotational ? "urad" : "um"},
                     {"table", e.table},
                     {"parameters", e.parameters}});
  return Json{{"seed", draw.seed}, {"drawn", drawn}};
}

Json to_json(const PoseCheck& c, std::span<const ReachedPose> poses, bool per_pose) {
  Json j = pose_summary(c);
  if (per_pose) {
    Json arr = Json::array();
    for (std::size_t i = 0; i < c.poses.size(); ++i) {
      const auto& d = c.poses[i];
      arr.push_back({{"line", i < poses.size() ? poses[i].line : 0},
                     {"dx_um", d.error.x() * 1e3},
                     {"dy_um", d.error.y() * 1e3},
                     {"dz_um", d.error.z() * 1e3},
                     {"norm_um", d.error.norm() * 1e3},
                     {"direction_urad", d.direction_error * 1e6}});
    }
    j["errors"] = arr;
  }
  return j;
}

Json to_json(const CampaignResult& r, const Machine& m) {
  Json j;
  j["machine"] = m.name;
  j["reference"] = r.reference == BallReference::Nominal      ? "nominal"
                   : r.reference == BallReference::Identified ? "identified"
                                                              : "mean";
  j["facets"] = r.facets;
  j["before"] = summary(r.before, r.probed);
  j["after"] = summary(r.after, r.probed);
  j["improvement"] = r.after.rms > 0 ? Json(r.before.rms / r.after.rms) : Json(nullptr);
  std::vector<char> rotary;
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Rotary) rotary.push_back(ax.letter);
  Json probed = Json::array();
  for (const auto& d : r.probed) {
    Json rot = Json::object();
    for (std::size_t k = 0; k < d.rotary.size() && k < rotary.size(); ++k)
      rot[std::string(1, rotary[k])] = d.rotary[k] / kRadPerDeg;
    probed.push_back({{"record", d.record},
                      {"indexation", d.indexation},
                      {"feature", d.feature},
                      {"rotary_deg", rot},
                      {"line_before", d.line_before},
                      {"line_after", d.line_after},
                      {"before_um", um3(d.before)},
                      {"after_um", um3(d.after)}});
  }
  j["probed"] = probed;
  if (r.identification) {
    const auto& id = *r.identification;
    j["identification"] = {{"source", id.source},
                           {"converged", id.converged},
                           {"residuals", id.residuals},
                           {"unknowns", id.unknowns},
                           {"rank", id.rank},
                           {"rms_um", {{"ball", id.rms_ball * 1e3}, {"facet", id.rms_facet * 1e3}}},
                           {"sigma0", id.sigma0},
                           {"unidentifiable", id.unidentifiable}};
  } else {
    j["identification"] = nullptr;
  }
  Json params = Json::array();
  for (const auto& p : r.parameters)
    params.push_back({{"name", p.name},
                      {"unit", p.unit},
                      {"value", p.value},
                      {"u", finite_or_null(p.u)},
                      {"truth", p.truth ? Json(*p.truth) : Json(nullptr)},
                      {"deviation", p.truth ? Json(p.deviation) : Json(nullptr)},
                      {"ratio", finite_or_null(p.ratio)}});
  j["parameters"] = params;
  Json missing = Json::array();
  for (const auto& [name, value] : r.not_estimated) missing.push_back({{"name", name}, {"value", value}});
  j["not_estimated"] = missing;
  j["max_ratio"] = r.parameters.empty() ? Json(nullptr) : Json(r.max_ratio);
  j["beyond_3u"] = r.beyond_3u;
  j["random_poses"] = {{"before", r.poses_before ? pose_summary(*r.poses_before) : Json(nullptr)},
                       {"after", r.poses_after ? pose_summary(*r.poses_after) : Json(nullptr)}};
  j["probing_noise_um"] = r.probing_noise > 0 ? Json(r.probing_noise * 1e3) : Json(nullptr);
  j["goals"] = {{"residual", r.residual_goal ? Json(*r.residual_goal) : Json(nullptr)},
                {"parameters", r.parameter_goal ? Json(*r.parameter_goal) : Json(nullptr)}};
  return j;
}

}  // namespace mtcal
