// JSON of the prediction results: the documented keys of regress, predict, separate and process-error --json.
#include "mtcal/io/json/prediction_json.hpp"

#include <cmath>

namespace mtcal {

Json to_json(const FitResult& f) {
  Json p = Json::object();
  const auto names = parameter_names(f.model.spec);
  for (std::size_t k = 0; k < names.size(); ++k)
    p[names[k]] = {{"value", number_or_null(f.model.p[k])},
                   {"stddev", number_or_null(f.stddev[k])},
                   {"at_bound", k < f.at_bound.size() && f.at_bound[k]},
                   {"identified", k < f.identified.size() && f.identified[k]}};
  return {{"model", f.model.spec.label()},
          {"form", std::string(to_string(f.model.spec.form))},
          {"parameters", p},
          {"identifiable", f.identifiable},
          {"rss", number_or_null(f.rss)},
          {"sigma", number_or_null(f.sigma)},
          {"dof", f.dof},
          {"r_squared", number_or_null(f.r_squared)},
          {"aicc", number_or_null(f.aicc)},
          {"backward",
           {{"mean", f.backward.mean},
            {"max", f.backward.max},
            {"mean_relative", number_or_null(f.backward.mean_relative)},
            {"abs_diff", f.backward.abs_diff}}},
          {"loocv_rmse", f.loocv_rmse ? Json(*f.loocv_rmse) : Json(nullptr)},
          {"loocv_method", f.loocv_method.empty() ? Json(nullptr) : Json(f.loocv_method)}};
}

Json to_json(const ModelComparison& c, const std::string& file, const std::string& x, const std::string& y,
             std::size_t n, const std::string& report) {
  Json j;
  j["file"] = file;
  j["x"] = x;
  j["y"] = y;
  j["n"] = n;
  j["fits"] = Json::array();
  for (const auto& f : c.fits) j["fits"].push_back(to_json(f));
  j["skipped"] = Json::array();
  for (const auto& s : c.skipped) j["skipped"].push_back({{"model", s.spec.label()}, {"reason", s.reason}});
  if (!c.by_backward.empty()) j["best_backward"] = c.fits[c.by_backward[0]].model.spec.label();
  if (!c.by_loocv.empty()) j["best_loocv"] = c.fits[c.by_loocv[0]].model.spec.label();
  if (!report.empty()) j["report"] = report;
  return j;
}

Json to_json(const PredictionRun& run, const PredictionModel& m) {
  const PredictionPoints& t = run.points;
  Json j;
  j["model"] = m.file;
  j["source"] = t.source;
  j["components"] = Json::array();
  for (const auto& c : m.components)
    j["components"].push_back(
        {{"name", c.name}, {"axis", c.axis ? std::string(1, c.axis) : std::string("none")}, {"source", c.source}});
  j["points"] = Json::array();
  for (std::size_t r = 0; r < run.predictions.size(); ++r) {
    const auto& p = run.predictions[r];
    Json in = Json::object(), comps = Json::object();
    for (std::size_t k = 0; k < t.columns.size(); ++k) in[t.columns[k]] = t.rows[r][k];
    for (std::size_t k = 0; k < m.components.size(); ++k) comps[m.components[k].name] = p.values[k];
    j["points"].push_back(
        {{"line", t.lines[r]}, {"input", in}, {"components", comps}, {"ex", p.e[0]}, {"ey", p.e[1]}, {"ez", p.e[2]}});
  }
  j["warnings"] = run.warnings;
  if (!run.compensation.empty()) {
    j["compensation"] = Json::array();
    for (const auto& c : run.compensation)
      j["compensation"].push_back(
          {{"step", c.step}, {"offset_x", c.offset[0]}, {"offset_y", c.offset[1]}, {"offset_z", c.offset[2]}});
  }
  return j;
}

Json to_json(const PositionSeparation& s, const std::string& file) {
  Json j;
  j["file"] = file;
  j["kind"] = "position";
  j["steps"] = Json::array();
  for (const auto& p : s.steps)
    j["steps"].push_back({{"axis", std::string(1, p.axis)},
                          {"step", p.step},
                          {"distance", p.distance},
                          {"e_pos", p.e_pos},
                          {"count", p.count}});
  j["fits"] = Json::object();
  for (const auto& [name, f] : s.fits) j["fits"][name] = to_json(f);
  return j;
}

Json to_json(const ControlSeparation& s, const std::string& file) {
  Json j;
  j["file"] = file;
  j["kind"] = "control";
  j["quantity"] = s.quantity;
  j["a"] = s.a;
  j["b"] = s.b;
  j["steps"] = Json::array();
  for (const auto& c : s.steps)
    j["steps"].push_back(
        {{"axis", std::string(1, c.axis)}, {"step", c.step}, {"distance", c.distance}, {s.quantity, c.value}});
  j["warnings"] = s.warnings;
  return j;
}

Json to_json(const ProcessErrorStudy& s) {
  Json j;
  j["tool"] = {{"diameter", s.tool.diameter},          {"teeth", s.tool.teeth},
               {"helix_deg", s.tool.helix_deg},        {"overhang", s.tool.overhang},
               {"flute_length", s.tool.flute_length},  {"flute_diameter_ratio", s.tool.flute_diameter_ratio},
               {"young_modulus", s.tool.young_modulus}};
  j["coefficients"] = {{"ktc", s.k.ktc}, {"krc", s.k.krc}, {"kte", s.k.kte}, {"kre", s.k.kre}};
  j["cut"] = {{"radial_depth", s.cut.radial_depth},
              {"axial_depth", s.cut.axial_depth},
              {"spindle_speed", s.cut.spindle_speed},
              {"down_milling", s.cut.down_milling}};
  j["points"] = Json::array();
  for (const auto& p : s.points)
    j["points"].push_back({{"feed", p.feed},
                           {"fz", p.fz},
                           {"mean_fx", p.forces.mean_x},
                           {"mean_fy", p.forces.mean_y},
                           {"peak_fy", p.forces.peak_y},
                           {"e_prog", p.e_prog}});
  if (s.calibration) {
    Json c = to_json(s.calibration->fit);
    c["measured"] = s.measured;
    j["calibration"] = c;
  }
  return j;
}

}  // namespace mtcal
