// JSON of the acceptance-test evaluations (io/json/evaluation_json.hpp); keys documented in docs/evaluations.md.
#include "mtcal/io/json/evaluation_json.hpp"

#include <initializer_list>
#include <utility>

namespace mtcal {
namespace {

template <class T>
Json or_null(const std::optional<T>& v) {
  return v ? Json(*v) : Json(nullptr);
}

}  // namespace

Json to_json(const PositioningEvaluation& e) {
  Json j;
  for (const auto& [k, v] : std::initializer_list<std::pair<const char*, double>>{{"A", e.A},
                                                                                  {"A_up", e.A_up},
                                                                                  {"A_down", e.A_down},
                                                                                  {"B", e.B},
                                                                                  {"B_mean", e.B_mean},
                                                                                  {"R", e.R},
                                                                                  {"R_up", e.R_up},
                                                                                  {"R_down", e.R_down},
                                                                                  {"E", e.E},
                                                                                  {"E_up", e.E_up},
                                                                                  {"E_down", e.E_down},
                                                                                  {"M", e.M}})
    j[k] = v;
  j["unit"] = e.unit;
  j["target_unit"] = e.target_unit;
  j["runs"] = e.runs;
  j["directions"] = e.directions == TestDirections::Both     ? "both"
                    : e.directions == TestDirections::UpOnly ? "up"
                                                             : "down";
  j["notes"] = e.notes;
  Json ts = Json::array();
  for (const auto& t : e.targets)
    ts.push_back({{"target", t.target},
                  {"n_up", t.n_up},
                  {"n_down", t.n_down},
                  {"mean_up", t.mean_up},
                  {"mean_down", t.mean_down},
                  {"mean", t.mean},
                  {"B", t.reversal},
                  {"s_up", t.s_up},
                  {"s_down", t.s_down},
                  {"R_up", t.R_up},
                  {"R_down", t.R_down},
                  {"R", t.R}});
  j["targets"] = ts;
  return j;
}

Json to_json(const CircularDeviation& d) {
  return {{"points", d.points},
          {"G", d.G},
          {"G_minimum_zone", d.G_minimum_zone},
          {"centre", {d.centre_x, d.centre_y}},
          {"minimum_zone_centre", {d.mz_centre_x, d.mz_centre_y}},
          {"F_max", d.F_max},
          {"F_min", d.F_min},
          {"F_mean", d.F_mean}};
}

Json to_json(const TraceDiagnosis& d) {
  Json dj = Json::object();
  for (const auto& term : d.terms)
    dj[term.name] = {{"value", term.value}, {"u", term.uncertainty}, {"unit", term.unit}, {"share", term.share}};
  return dj;
}

Json to_json(const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis, const std::string& plane,
             double radius, double feed) {
  Json j;
  j["plane"] = plane;
  j["radius"] = radius;
  if (feed > 0) j["feed"] = feed;
  j["G_cw"] = e.cw ? Json(e.cw->G) : Json(nullptr);
  j["G_ccw"] = e.ccw ? Json(e.ccw->G) : Json(nullptr);
  j["G_b"] = or_null(e.G_b);
  j["H"] = or_null(e.H);
  j["F_max"] = e.F_max;
  j["F_min"] = e.F_min;
  j["F_mean_bidirectional"] = or_null(e.F_mean_bidirectional);
  if (e.cw) j["cw"] = to_json(*e.cw);
  if (e.ccw) j["ccw"] = to_json(*e.ccw);
  if (diagnosis) {
    j["diagnostics"] = to_json(*diagnosis);
    j["diagnostics_residual_rms_um"] = diagnosis->residual_rms;
  }
  j["units"] = "mm";
  return j;
}

Json to_json(const MethodComparison& c) {
  Json j;
  j["file"] = c.source;
  j["methods"] = {c.methods[0], c.methods[1]};
  Json params = Json::object();
  for (const auto& p : c.parameters) {
    Json mean, stdev, n;
    for (std::size_t k = 0; k < 2; ++k) {
      mean[c.methods[k]] = or_null(p.stats[k].mean);
      stdev[c.methods[k]] = or_null(p.stats[k].stdev);
      n[c.methods[k]] = p.stats[k].n;
    }
    params[p.name] = {{"mean", mean},
                      {"stdev", stdev},
                      {"abs_diff", or_null(p.abs_diff)},
                      {"overlap", or_null(p.overlap)},
                      {"pearson_r", or_null(p.pearson_r)},
                      {"n", n},
                      {"paired", p.paired}};
  }
  j["parameters"] = params;
  const auto& s = c.summary;
  j["summary"] = {{"parameters", s.parameters},
                  {"both_methods", s.both_methods},
                  {"one_method_only", s.one_method_only},
                  {"overlap", s.overlap},
                  {"no_overlap", s.no_overlap},
                  {"with_correlation", s.with_correlation},
                  {"strong_correlation", s.strong_correlation},
                  {"strong_positive", s.strong_positive},
                  {"strong_negative", s.strong_negative},
                  {"strong_threshold", kStrongCorrelation}};
  return j;
}

}  // namespace mtcal
