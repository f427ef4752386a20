// mtcal simulate, identify, identifiability: indirect calibration from probing (Viprey 2015,
// Mohammed 2019 SAMBA/TANGO).
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

// Options shared by identify and identifiability: what to estimate and how residuals weigh.
struct EstimateOptions {
  std::vector<std::string> estimate, scale_bars;
  bool pretravel = false;
  double sigma_um = 1.0;
  double rank_tolerance = 1e-8;
};

void add_estimate_options(CLI::App* c, EstimateOptions& e, bool required) {
  auto* opt = c->add_option("--estimate", e.estimate,
                            "Parameters (EX0C, EXX.1, EXX.b) or errors (EXX: all its coefficients) to estimate, "
                            "comma-separated or repeated; the artefact's ball centres and facet offsets always are")
                  ->delimiter(',');
  if (required) opt->required();
  c->add_option("--scale-bar", e.scale_bars, "Calibrated distance between two balls: BALL:BALL:LENGTH (mm), e.g. 1:2:304.8; repeatable");
  c->add_flag("--pretravel", e.pretravel, "Also estimate one probe pre-travel for all facet touches (mm)");
  c->add_option("--sigma-um", e.sigma_um, "Standard deviation of a reading, um (weights; the uncertainties use the residuals)")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--rank-tolerance", e.rank_tolerance, "Relative singular value below which a direction is unidentifiable")
      ->check(CLI::Range(1e-15, 0.1))
      ->capture_default_str();
}

IdentificationOptions to_options(const EstimateOptions& e) {
  IdentificationOptions o;
  o.estimate = e.estimate;
  for (const auto& s : e.scale_bars) o.scale_bars.push_back(parse_scale_bar(s));
  o.estimate_pretravel = e.pretravel;
  o.sigma_ball = o.sigma_facet = o.sigma_scale_bar = e.sigma_um * 1e-3;
  o.rank_tolerance = e.rank_tolerance;
  return o;
}

json identifiability_json(const Identifiability& id) {
  return {{"rank", id.rank},
          {"unknowns", id.columns.size()},
          {"condition", std::isfinite(id.condition) ? json(id.condition) : json(nullptr)},
          {"condition_identifiable", id.condition_identifiable},
          {"singular_values", id.singular_values},
          {"identifiable", id.identifiable},
          {"unidentifiable", id.unidentifiable},
          {"null_directions", id.null_directions}};
}

void print_identifiability(const Identifiability& id) {
  std::cout << fmt::format("unknowns {} (machine parameters and the artefact's), rank {}; condition {} (all), {:.4g} "
                           "(the identifiable ones)\n",
                           id.columns.size(), id.rank,
                           std::isfinite(id.condition) ? fmt::format("{:.4g}", id.condition) : std::string("infinite"),
                           id.condition_identifiable);
  if (!id.identifiable.empty()) {
    std::cout << "identifiable:";
    for (const auto& n : id.identifiable) std::cout << " " << n;
    std::cout << "\n";
  }
  if (!id.unidentifiable.empty()) {
    std::cout << "NOT identifiable (excluded):";
    for (const auto& n : id.unidentifiable) std::cout << " " << n;
    std::cout << "\n";
  }
  for (const auto& d : id.null_directions) std::cout << "  cannot be separated: " << d << "\n";
}

// ---------------------------------------------------------------------------------------------

struct SimulateOptions {
  ModelOptions model;
  std::string plan, out;
  double noise_um = 0.0, artefact_um = 0.0;
  std::uint64_t seed = 1;
  std::vector<std::string> scale_bars;
  bool json_out = false;
};

int run_simulate(const SimulateOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.plan);
  check_outputs(inputs, {o.out});
  const Machine m = load(o.model);
  const ProbingPlan plan = read_probing_csv(m, o.plan);
  SimulationOptions so;
  so.noise = o.noise_um * 1e-3;
  so.artefact_error = o.artefact_um * 1e-3;
  so.seed = o.seed;
  for (const auto& s : o.scale_bars) so.scale_bars.push_back(parse_scale_bar(s));
  std::unique_ptr<AtomicFile> file;
  if (!o.out.empty()) file = std::make_unique<AtomicFile>(o.out);
  const Simulation sim = simulate_probing(m, plan, so);
  if (file) {
    file->stream() << fmt::format("# Simulated by mtcal simulate: machine {}, plan {}, noise {:g} um, artefact error {:g} um, seed {}\n",
                                  o.model.machine, o.plan, o.noise_um, o.artefact_um, o.seed)
                   << probing_csv(m, sim.measurements);
    file->commit();
  }
  json truth_balls = json::object(), truth_facets = json::object();
  for (std::size_t f = 0; f < plan.features.size(); ++f) {
    if (plan.features[f].kind == ProbeFeature::Kind::Ball)
      truth_balls[plan.features[f].id] = {sim.truth.ball[f].x(), sim.truth.ball[f].y(), sim.truth.ball[f].z()};
    else
      truth_facets[plan.features[f].id] = sim.truth.offset[f];
  }
  if (o.json_out) {
    json j;
    j["records"] = sim.measurements.records.size();
    j["residuals"] = sim.measurements.residual_count();
    j["noise_um"] = o.noise_um;
    j["artefact_error_um"] = o.artefact_um;
    j["seed"] = o.seed;
    j["truth"] = {{"balls", truth_balls}, {"facets", truth_facets}};
    if (!o.out.empty()) j["out"] = o.out;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("simulated {} probings ({} balls and facets) of {} on {}; noise {:g} um, artefact error {:g} um, seed {}\n",
                           sim.measurements.records.size(), plan.features.size(), o.plan, m.name, o.noise_um, o.artefact_um, o.seed);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------

struct IdentifyOptions {
  ModelOptions model;
  EstimateOptions est;
  std::string measurements, out, report, truth, workspace, loss = "none";
  std::size_t monte_carlo = 0;
  std::uint64_t seed = 1;
  int threads = 0;
  bool json_out = false;
};

int run_identify(const IdentifyOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.measurements);
  inputs.push_back(o.truth);
  check_outputs(inputs, {o.out, o.report});
  const Machine prior = load(o.model);
  const ProbingPlan meas = read_probing_csv(prior, o.measurements);
  IdentificationOptions opt = to_options(o.est);
  opt.loss = o.loss == "huber" ? IdentificationOptions::Loss::Huber
             : o.loss == "cauchy" ? IdentificationOptions::Loss::Cauchy
                                  : IdentificationOptions::Loss::None;
  std::optional<Machine> truth;
  if (!o.truth.empty()) truth = load_machine(o.truth);
  std::vector<std::vector<double>> workspace;
  if (!o.workspace.empty()) workspace = checked_grid(prior, o.workspace, false, 2'000'000);
  if ((truth || o.monte_carlo > 0) && workspace.empty() && !o.truth.empty())
    throw InputError({"--truth", 0, ""}, "--truth needs --workspace (the grid over which the models are compared)");
  std::unique_ptr<AtomicFile> file;
  if (!o.out.empty()) file = std::make_unique<AtomicFile>(o.out);
  if (!o.report.empty()) AtomicFile probe(o.report);

  const auto t0 = Clock::now();
  const IdentificationResult r = identify(prior, meas, opt);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::optional<MonteCarloResult> mc;
  double mc_seconds = 0;
  if (o.monte_carlo > 0) {
    MonteCarloOptions mo;
    mo.runs = o.monte_carlo;
    mo.seed = o.seed;
    mo.threads = o.threads;
    mo.workspace = workspace;
    const auto t1 = Clock::now();
    mc = monte_carlo(prior, meas, opt, r, mo);
    mc_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  }
  std::optional<ModelDeviation> dev;
  if (truth) dev = model_deviation(r.machine, *truth, workspace);
  std::optional<double> va;
  if (!workspace.empty()) va = volumetric_accuracy(grid_error_map(ErrorModel(r.machine), workspace).error).va.value;

  if (file) {
    std::vector<ErrorName> errors;
    for (const auto& p : r.parameters) {
      const auto e = prior.parameters()[*prior.parameter_index(p.name)].error;
      if (std::find(errors.begin(), errors.end(), e) == errors.end()) errors.push_back(e);
    }
    std::string comment = fmt::format("Identified by mtcal identify from {} ({} residuals, {} unknowns, rank {}, rms {:.3f} um)",
                                      o.measurements, r.residuals, r.unknowns, r.identifiability.rank,
                                      std::max(r.rms_ball, r.rms_facet) * 1e3);
    for (const auto& p : r.parameters) comment += fmt::format("\n{} = {:.9g} {} +- {:.3g} (standard uncertainty)", p.name, p.value, p.unit, p.u);
    for (const auto& u : r.identifiability.unidentifiable) comment += "\nnot identifiable, left at the machine's value: " + u;
    file->stream() << parameters_yaml(r.machine, errors, comment);
    file->commit();
  }

  if (!o.report.empty()) {
    Report rep("Identification of " + prior.name, command_line());
    rep.set_machine(prior);
    for (const auto& p : o.model.params) rep.add_input("parameter file", p);
    rep.add_input("measurements", o.measurements);
    if (truth) rep.add_input("imposed machine", o.truth);
    rep.add_figure("residual RMS", fmt::format("{:.3f} (balls), {:.3f} (facets)", r.rms_ball * 1e3, r.rms_facet * 1e3), "µm");
    rep.add_figure("rank / unknowns", fmt::format("{} / {}", r.identifiability.rank, r.unknowns), "");
    rep.add_figure("condition number", fmt::format("{:.4g}", r.identifiability.condition), "(scaled Jacobian)");
    if (va) rep.add_figure("VA of the identified model", fmt::format("{:.3f}", *va * 1e3), "µm over " + o.workspace);
    if (dev) rep.add_figure("e_V against the imposed machine", fmt::format("max {:.4f}, rms {:.4f}", dev->max * 1e3, dev->rms * 1e3), "µm");
    for (const auto& u : r.identifiability.unidentifiable) rep.add_warning("Not identifiable from these measurements, excluded: " + u + ".");
    if (!r.converged) rep.add_warning("The solver did not report convergence: " + r.termination);
    rep.add_section("Estimates");
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < r.parameters.size(); ++i) {
      const auto& p = r.parameters[i];
      std::vector<std::string> row{p.name, fmt::format("{:.6g}", p.value), fmt::format("{:.3g}", p.u), p.unit};
      if (mc) row.push_back(fmt::format("{:.3g}", mc->stdev[i]));
      if (truth) row.push_back(fmt::format("{:.6g}", truth->parameter(*truth->parameter_index(p.name))));
      rows.push_back(row);
    }
    std::vector<std::string> cols{"parameter", "value", "u (covariance)", "unit"};
    if (mc) cols.push_back(fmt::format("u (Monte Carlo, {} runs)", mc->runs));
    if (truth) cols.push_back("imposed");
    rep.add_table("Estimated parameters (standard uncertainties)", cols, rows);
    json z = json::array(), names = json::array();
    for (std::size_t i = 0; i < r.parameters.size(); ++i) {
      names.push_back(r.parameters[i].name);
      json row = json::array();
      for (std::size_t j = 0; j < r.parameters.size(); ++j) row.push_back(r.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
      z.push_back(row);
    }
    if (!r.parameters.empty())
      rep.add_plot("Correlation of the estimates",
                   {{"data", {{{"type", "heatmap"}, {"x", names}, {"y", names}, {"z", z}, {"zmin", -1}, {"zmax", 1}, {"colorscale", "RdBu"}}}},
                    {"layout", {{"yaxis", {{"autorange", "reversed"}}}}}});
    json sv = json::array(), idx = json::array();
    for (std::size_t i = 0; i < r.identifiability.singular_values.size(); ++i) idx.push_back(i + 1), sv.push_back(r.identifiability.singular_values[i]);
    rep.add_plot("Singular values of the scaled Jacobian (all unknowns)",
                 {{"data", {{{"type", "scatter"}, {"mode", "markers+lines"}, {"x", idx}, {"y", sv}}}},
                  {"layout", {{"yaxis", {{"type", "log"}, {"title", {{"text", "singular value"}}}}}, {"xaxis", {{"title", {{"text", "index"}}}}}}}});
    rep.add_paragraph(fmt::format("Solver: {} after {} iterations; cost {:.6g} → {:.6g}; {} residuals, {} unknowns; σ0 {:.4g}.",
                                  r.termination, r.iterations, r.initial_cost, r.final_cost, r.residuals, r.unknowns, r.sigma0));
    rep.write(o.report);
  }

  if (o.json_out) {
    json j;
    j["termination"] = r.termination;
    j["converged"] = r.converged;
    j["iterations"] = r.iterations;
    j["seconds"] = seconds;
    j["residuals"] = r.residuals;
    j["unknowns"] = r.unknowns;
    j["rank"] = r.identifiability.rank;
    j["condition"] = std::isfinite(r.identifiability.condition) ? json(r.identifiability.condition) : json(nullptr);
    j["singular_values"] = r.identifiability.singular_values;
    j["rms_um"] = {{"ball", r.rms_ball * 1e3}, {"facet", r.rms_facet * 1e3}, {"scale_bar", r.rms_scale_bar * 1e3}};
    j["sigma0"] = r.sigma0;
    j["initial_cost"] = r.initial_cost;
    j["final_cost"] = r.final_cost;
    json params = json::object();
    for (std::size_t i = 0; i < r.parameters.size(); ++i) {
      const auto& p = r.parameters[i];
      json e = {{"value", p.value}, {"u", p.u}, {"unit", p.unit}};
      if (mc) e["u_monte_carlo"] = mc->stdev[i], e["mean_monte_carlo"] = mc->mean[i];
      if (truth) e["imposed"] = truth->parameter(*truth->parameter_index(p.name));
      params[p.name] = e;
    }
    j["parameters"] = params;
    json corr = json::array();
    for (Eigen::Index i = 0; i < r.correlation.rows(); ++i) {
      json row = json::array();
      for (Eigen::Index k = 0; k < r.correlation.cols(); ++k) row.push_back(r.correlation(i, k));
      corr.push_back(row);
    }
    j["correlation"] = corr;
    j["unidentifiable"] = r.identifiability.unidentifiable;
    j["null_directions"] = r.identifiability.null_directions;
    json art = {{"balls", json::object()}, {"facets", json::object()}};
    for (std::size_t f = 0; f < meas.features.size(); ++f) {
      if (meas.features[f].kind == ProbeFeature::Kind::Ball)
        art["balls"][meas.features[f].id] = {r.artefact.ball[f].x(), r.artefact.ball[f].y(), r.artefact.ball[f].z()};
      else
        art["facets"][meas.features[f].id] = r.artefact.offset[f];
    }
    j["artefact"] = art;
    if (r.pretravel_estimated) j["pretravel"] = {{"value", r.pretravel}, {"u", r.pretravel_u}};
    if (mc) j["monte_carlo"] = {{"runs", mc->runs}, {"failed", mc->failed}, {"seconds", mc_seconds}, {"seed", o.seed},
                                 {"va_mean", workspace.empty() ? json(nullptr) : json(mc->va_mean)},
                                 {"va_stdev", workspace.empty() ? json(nullptr) : json(mc->va_stdev)},
                                 {"map_stdev_max", workspace.empty() ? json(nullptr) : json(mc->map_stdev_max)}};
    if (va) j["va"] = *va;
    if (dev) j["e_v"] = {{"max", dev->max}, {"rms", dev->rms}};
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{} residuals, {} unknowns, rank {}, condition {:.4g}; {} in {} iterations ({:.1f} ms)\n", r.residuals,
                           r.unknowns, r.identifiability.rank, r.identifiability.condition, r.converged ? "converged" : "NOT converged",
                           r.iterations, seconds * 1e3);
  std::cout << fmt::format("residual rms: balls {:.3f} um, facets {:.3f} um, scale bars {:.3f} um; sigma0 {:.3g}\n", r.rms_ball * 1e3,
                           r.rms_facet * 1e3, r.rms_scale_bar * 1e3, r.sigma0);
  std::cout << fmt::format("{:<10} {:>14} {:>12} {:<8}{}{}\n", "parameter", "value", "u", "unit", mc ? "   u (Monte Carlo)" : "",
                           truth ? "      imposed" : "");
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const auto& p = r.parameters[i];
    std::cout << fmt::format("{:<10} {:>14.6g} {:>12.3g} {:<8}", p.name, p.value, p.u, p.unit);
    if (mc) std::cout << fmt::format(" {:>17.3g}", mc->stdev[i]);
    if (truth) std::cout << fmt::format(" {:>12.6g}", truth->parameter(*truth->parameter_index(p.name)));
    std::cout << "\n";
  }
  for (const auto& u : r.identifiability.unidentifiable) std::cout << "NOT identifiable, excluded: " << u << "\n";
  for (const auto& d : r.identifiability.null_directions) std::cout << "  cannot be separated: " << d << "\n";
  if (r.pretravel_estimated) std::cout << fmt::format("pre-travel {:.4f} um +- {:.4f}\n", r.pretravel * 1e3, r.pretravel_u * 1e3);
  if (mc) std::cout << fmt::format("Monte Carlo: {} runs ({} failed) in {:.2f} s\n", mc->runs, mc->failed, mc_seconds);
  if (va) {
    std::cout << fmt::format("VA of the identified model over {}: {:.3f} um", o.workspace, *va * 1e3);
    if (mc)
      std::cout << fmt::format(" (Monte Carlo {:.3f} +- {:.3f} um; error map's largest standard deviation {:.3f} um)",
                               mc->va_mean * 1e3, mc->va_stdev * 1e3, mc->map_stdev_max * 1e3);
    std::cout << "\n";
  }
  if (dev) std::cout << fmt::format("e_V against {}: max {:.4f} um, rms {:.4f} um\n", o.truth, dev->max * 1e3, dev->rms * 1e3);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------

struct IdentifiabilityOptions {
  ModelOptions model;
  EstimateOptions est;
  std::string plan;
  std::vector<std::string> candidates, always;
  std::size_t choose = 0, list = 20;
  std::string sort = "condition";
  int threads = 0;
  bool json_out = false;
};

int run_identifiability(const IdentifiabilityOptions& o) {
  const Machine m = load(o.model);
  const ProbingPlan plan = read_probing_csv(m, o.plan);
  IdentificationOptions opt = to_options(o.est);
  if (o.choose == 0) {
    if (o.est.estimate.empty()) throw InputError({"--estimate", 0, ""}, "expected --estimate, or --candidates with --choose");
    const Identifiability id = identifiability(m, plan, opt);
    if (o.json_out) {
      json j = identifiability_json(id);
      j["columns"] = id.columns;
      std::cout << j.dump(2) << "\n";
    } else {
      print_identifiability(id);
    }
    return 0;
  }
  if (o.candidates.empty()) throw InputError({"--candidates", 0, ""}, "--choose needs --candidates");
  SubsetOptions so;
  so.candidates = o.candidates;
  so.always = o.always;
  so.choose = o.choose;
  so.threads = o.threads;
  so.rank_tolerance = std::max(o.est.rank_tolerance, 1e-7);  // the normal matrix resolves no finer
  so.keep = o.list;
  so.by_residue = o.sort == "residue";
  const auto t0 = Clock::now();
  const SubsetAnalysis a = full_rank_subsets(m, plan, so, opt);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const std::vector<std::string>& names = a.candidates;  // resolved: errors expanded, duplicates removed
  auto members = [&](const ParameterSubset& s) {
    std::vector<std::string> v;
    for (std::size_t i : s.members) v.push_back(i < names.size() ? names[i] : std::to_string(i));
    return v;
  };
  if (o.json_out) {
    json j;
    j["candidates"] = names;  // resolved parameter names
    j["always"] = o.always;
    j["choose"] = o.choose;
    j["examined"] = a.examined;
    j["count"] = a.full_rank;
    j["pruned"] = a.pruned;
    j["seconds"] = seconds;
    j["subsets"] = json::array();
    for (const auto& s : a.subsets) {
      json e = {{"parameters", members(s)}, {"condition", s.condition}};
      if (!std::isnan(s.residue)) e["residue"] = s.residue;
      j["subsets"].push_back(e);
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{} of the {} subsets of {} among {} candidates give a full-rank model ({:.3f} s, {} partial subsets pruned)\n",
                           a.full_rank, a.examined, o.choose, names.size(), seconds, a.pruned);
  for (const auto& s : a.subsets) {
    std::string line = fmt::format("  cond {:>10.4g}", s.condition);
    if (!std::isnan(s.residue)) line += fmt::format("  residue {:.4g}", s.residue);
    line += " :";
    for (const auto& n : members(s)) line += " " + n;
    std::cout << line << "\n";
  }
  if (a.full_rank > a.subsets.size()) std::cout << fmt::format("  ... {} more (--list)\n", a.full_rank - a.subsets.size());
  return 0;
}

}  // namespace

std::vector<Command> add_identification_commands(CLI::App& app) {
  std::vector<Command> out;
  {
    auto o = std::make_shared<SimulateOptions>();
    auto* c = app.add_subcommand("simulate", "Virtual machine (Viprey 2015 fig. 4): the readings a machine gives for a probing "
                                             "plan (balls and facets at indexations), with noise and an uncalibrated artefact");
    add_model_options(c, o->model);
    c->add_option("--plan", o->plan, "Probing plan CSV (docs/identification.md)")->required();
    c->add_option("--noise-um", o->noise_um, "Standard deviation of each reading, um")->check(CLI::NonNegativeNumber & kFinite)->capture_default_str();
    c->add_option("--artefact-error-um", o->artefact_um, "Standard deviation of the features' true positions about the plan's, um")
        ->check(CLI::NonNegativeNumber & kFinite)
        ->capture_default_str();
    c->add_option("--seed", o->seed, "Random seed")->capture_default_str();
    c->add_option("--scale-bar", o->scale_bars, "Make two balls exactly this far apart: BALL:BALL:LENGTH (mm); repeatable");
    c->add_option("--out", o->out, "Measurement CSV to write (the plan's columns plus the readings X, Y, Z)");
    c->add_flag("--json", o->json_out, "Machine-readable output: records residuals noise_um seed truth out");
    out.push_back({c, [o] { return run_simulate(*o); }});
  }
  {
    auto o = std::make_shared<IdentifyOptions>();
    auto* c = app.add_subcommand("identify", "Identify machine parameters from probing measurements: nonlinear least squares on "
                                             "the exact model (Ceres), rank, conditioning, uncertainties, what is not identifiable");
    add_model_options(c, o->model);
    c->add_option("--measurements", o->measurements, "Measurement CSV (docs/identification.md), e.g. from mtcal simulate")->required();
    add_estimate_options(c, o->est, true);
    c->add_option("--loss", o->loss, "Robust loss on each probing: none, huber or cauchy (scale 3 sigma)")
        ->check(CLI::IsMember({"none", "huber", "cauchy"}))
        ->capture_default_str();
    c->add_option("--monte-carlo", o->monte_carlo, "Runs of re-drawn noise for Monte Carlo uncertainties")->check(CLI::Range(0, 1000000));
    c->add_option("--seed", o->seed, "Seed of the Monte Carlo runs")->capture_default_str();
    c->add_option("--workspace", o->workspace, "Grid for the identified model's VA (and its Monte Carlo spread), e.g. "
                                               "\"X=-300:300:7,Y=-250:250:7,Z=-300:300:7,B=0:90:3\"");
    c->add_option("--truth", o->truth, "The imposed machine (simulations): e_V, the identified model against it over --workspace");
    c->add_option("--threads", o->threads, "Threads for Monte Carlo (0: all cores)")->check(CLI::Range(0, 1024));
    c->add_option("--out", o->out, "Parameter file with the identified errors (mtcal eval --params ...)");
    c->add_option("--report", o->report, "Write an HTML report");
    c->add_flag("--json", o->json_out, "Machine-readable output: parameters{value u} rank condition rms_um unidentifiable ...");
    out.push_back({c, [o] { return run_identify(*o); }});
  }
  {
    auto o = std::make_shared<IdentifiabilityOptions>();
    auto* c = app.add_subcommand("identifiability", "What a probing plan can identify: rank and singular values of the scaled "
                                                    "Jacobian, unidentifiable combinations; or every full-rank subset of K "
                                                    "candidate parameters (Viprey 2015)");
    add_model_options(c, o->model);
    c->add_option("--plan", o->plan, "Probing plan or measurement CSV")->required();
    add_estimate_options(c, o->est, false);
    c->add_option("--candidates", o->candidates, "Candidate parameters for the subset analysis")->delimiter(',');
    c->add_option("--choose", o->choose, "Subset size K")->check(CLI::Range(1, 64));
    c->add_option("--always", o->always, "Parameters in every subset (e.g. the tool mounting positions)")->delimiter(',');
    c->add_option("--list", o->list, "Subsets listed, best first")->capture_default_str();
    c->add_option("--sort", o->sort, "Rank subsets by condition number, or by residue of estimation (measurements only)")
        ->check(CLI::IsMember({"condition", "residue"}))
        ->capture_default_str();
    c->add_option("--threads", o->threads, "Threads (0: all cores)")->check(CLI::Range(0, 1024));
    c->add_flag("--json", o->json_out, "Machine-readable output: rank singular_values unidentifiable ...; with --choose: count subsets[parameters condition]");
    out.push_back({c, [o] { return run_identifiability(*o); }});
  }
  return out;
}

}  // namespace mtcal::cli
