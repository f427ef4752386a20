// JSON of the identification results: the documented keys of simulate, identify and identifiability --json.
#include "mtcal/io/json/identification_json.hpp"

#include <algorithm>
#include <cmath>

#include "mtcal/identification/fit_check.hpp"

namespace mtcal {

Json to_json(const Identifiability& id) {
  return {{"rank", id.rank},
          {"unknowns", id.columns.size()},
          {"condition", std::isfinite(id.condition) ? Json(id.condition) : Json(nullptr)},
          {"condition_identifiable", id.condition_identifiable},
          {"singular_values", id.singular_values},
          {"identifiable", id.identifiable},
          {"unidentifiable", id.unidentifiable},
          {"null_directions", id.null_directions},
          {"columns", id.columns}};
}

Json artefact_json(const std::vector<ProbeFeature>& features, const ArtefactState& state) {
  Json balls = Json::object(), facets = Json::object(), ballbars = Json::object(), lasers = Json::object();
  for (std::size_t f = 0; f < features.size(); ++f) {
    const Vec3& c = state.ball[f];
    switch (features[f].kind) {
      case ProbeFeature::Kind::Ball: balls[features[f].id] = {c.x(), c.y(), c.z()}; break;
      case ProbeFeature::Kind::Facet: facets[features[f].id] = state.offset[f]; break;
      case ProbeFeature::Kind::Ballbar:
        ballbars[features[f].id] = {{"pivot", {c.x(), c.y(), c.z()}}, {"length_offset", state.offset[f]}};
        break;
      case ProbeFeature::Kind::Laser: lasers[features[f].id] = state.offset[f]; break;
    }
  }
  Json j = {{"balls", balls}, {"facets", facets}};
  // Only with the instruments: the keys of probing alone as before.
  if (!ballbars.empty()) j["ballbars"] = ballbars;
  if (!lasers.empty()) j["lasers"] = lasers;
  return j;
}

Json to_json(const Simulation& sim, double noise_um, double artefact_error_um, std::uint64_t seed,
             const std::string& out) {
  Json j;
  j["records"] = sim.measurements.records.size();
  j["residuals"] = sim.measurements.residual_count();
  j["noise_um"] = noise_um;
  j["artefact_error_um"] = artefact_error_um;
  j["seed"] = seed;
  j["truth"] = artefact_json(sim.measurements.features, sim.truth);
  if (!out.empty()) j["out"] = out;
  return j;
}

Json to_json(const IdentificationRun& run, const std::string& out, const std::string& report) {
  const IdentificationResult& r = run.result;
  const auto& mc = run.monte_carlo;
  const bool truth = !run.imposed.empty() || run.deviation.has_value();
  Json j;
  j["termination"] = r.termination;
  j["converged"] = r.converged;
  j["iterations"] = r.iterations;
  j["seconds"] = run.seconds;
  j["residuals"] = r.residuals;
  j["unknowns"] = r.unknowns;
  j["rank"] = r.identifiability.rank;
  j["condition"] = std::isfinite(r.identifiability.condition) ? Json(r.identifiability.condition) : Json(nullptr);
  j["singular_values"] = r.identifiability.singular_values;
  j["rms_um"] = {{"ball", r.rms_ball * 1e3}, {"facet", r.rms_facet * 1e3}, {"scale_bar", r.rms_scale_bar * 1e3}};
  for (const auto kind : {ProbeFeature::Kind::Ballbar, ProbeFeature::Kind::Laser})
    if (std::any_of(run.features.begin(), run.features.end(), [&](const ProbeFeature& f) { return f.kind == kind; }))
      j["rms_um"][feature_kind_name(kind)] = (kind == ProbeFeature::Kind::Ballbar ? r.rms_ballbar : r.rms_laser) * 1e3;
  j["sigma0"] = r.sigma0;
  {
    const FitCheck f = check_fit(r);
    j["fit"] = {{"poor", f.poor},
                {"sigma0", f.sigma0},
                {"bound", std::isfinite(f.bound) ? Json(f.bound) : Json(nullptr)},
                {"probability", f.probability},
                {"degrees_of_freedom", f.degrees_of_freedom}};
  }
  j["initial_cost"] = r.initial_cost;
  j["final_cost"] = r.final_cost;
  Json params = Json::object();
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const auto& p = r.parameters[i];
    Json e = {{"value", p.value}, {"u", p.u}, {"unit", p.unit}};
    if (mc) e["u_monte_carlo"] = mc->stdev[i], e["mean_monte_carlo"] = mc->mean[i];
    if (truth && i < run.imposed.size()) e["imposed"] = run.imposed[i];
    params[p.name] = e;
  }
  j["parameters"] = params;
  Json corr = Json::array();
  for (Eigen::Index i = 0; i < r.correlation.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index k = 0; k < r.correlation.cols(); ++k) row.push_back(r.correlation(i, k));
    corr.push_back(row);
  }
  j["correlation"] = corr;
  j["unidentifiable"] = r.identifiability.unidentifiable;
  j["null_directions"] = r.identifiability.null_directions;
  j["artefact"] = artefact_json(run.features, r.artefact);
  if (r.pretravel_estimated) j["pretravel"] = {{"value", r.pretravel}, {"u", r.pretravel_u}};
  if (mc)
    j["monte_carlo"] = {{"runs", mc->runs},
                        {"failed", mc->failed},
                        {"seconds", run.monte_carlo_seconds},
                        {"seed", run.seed},
                        {"va_mean", run.workspace ? Json(mc->va_mean) : Json(nullptr)},
                        {"va_stdev", run.workspace ? Json(mc->va_stdev) : Json(nullptr)},
                        {"map_stdev_max", run.workspace ? Json(mc->map_stdev_max) : Json(nullptr)}};
  if (run.va) j["va"] = *run.va;
  if (run.deviation) j["e_v"] = {{"max", run.deviation->max}, {"rms", run.deviation->rms}};
  if (!out.empty()) j["out"] = out;
  if (!report.empty()) j["report"] = report;
  return j;
}

Json to_json(const SubsetAnalysis& a, const SubsetOptions& o, double seconds) {
  const std::vector<std::string>& names = a.candidates;  // resolved: errors expanded, duplicates removed
  Json j;
  j["candidates"] = names;
  j["always"] = o.always;
  j["choose"] = o.choose;
  j["examined"] = a.examined;
  j["count"] = a.full_rank;
  j["pruned"] = a.pruned;
  j["seconds"] = seconds;
  j["subsets"] = Json::array();
  for (const auto& s : a.subsets) {
    Json members = Json::array();
    for (std::size_t i : s.members) members.push_back(i < names.size() ? names[i] : std::to_string(i));
    Json e = {{"parameters", members}, {"condition", s.condition}};
    if (!std::isnan(s.residue)) e["residue"] = s.residue;
    j["subsets"].push_back(e);
  }
  return j;
}

Json estimated_parameters_json(const std::vector<EstimatedError>& params) {
  Json pj = Json::object();
  for (const auto& p : params) {
    if (p.motion) {
      for (std::size_t k = 0; k < p.motion->parameter_count(); ++k)
        if (p.motion->parameter(k) != 0)
          pj[p.name.str() + "." + p.motion->parameter_suffix(k)] = {{"value", p.motion->parameter(k)},
                                                                    {"u", p.uncertainty[k]}};
    } else {
      pj[p.name.str()] = {{"value", p.value}, {"u", p.uncertainty[0]}};
    }
  }
  return pj;
}

}  // namespace mtcal
