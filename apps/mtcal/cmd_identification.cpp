// mtcal simulate, identify, identifiability: indirect calibration from probing (Viprey 2015,
// Mohammed 2019 SAMBA/TANGO).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "budget.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/model/identified_parameters_file.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/identification/fit_check.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/report/identification.hpp"
#include "mtcal/report/recorded.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal::cli {
namespace {

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
  c->add_option("--scale-bar", e.scale_bars,
                "Calibrated distance between two balls: BALL:BALL:LENGTH (mm), e.g. 1:2:304.8; repeatable");
  c->add_flag("--pretravel", e.pretravel, "Also estimate one probe pre-travel for all facet touches (mm)");
  c->add_option("--sigma-um", e.sigma_um,
                "Standard deviation of a reading, um (weights; the uncertainties use the residuals)")
      ->transform(length_in(1e-3, "LENGTH"))
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--rank-tolerance", e.rank_tolerance,
                "Relative singular value below which a direction is unidentifiable")
      ->check(CLI::Range(1e-15, 0.1))
      ->capture_default_str();
}

IdentificationOptions to_options(const EstimateOptions& e) {
  IdentificationOptions o;
  o.estimate = e.estimate;
  o.estimate_source = "--estimate";
  for (const auto& s : e.scale_bars) o.scale_bars.push_back(parse_scale_bar(s, "--scale-bar"));
  o.estimate_pretravel = e.pretravel;
  o.sigma_ball = o.sigma_facet = o.sigma_scale_bar = o.sigma_ballbar = o.sigma_laser = e.sigma_um * 1e-3;
  o.rank_tolerance = e.rank_tolerance;
  return o;
}

// The dense Jacobian of a plan (residuals x unknowns) and its QR copies: a plan's memory grows with
// records x features. Unknowns: 3 per ball, 1 per facet (unknowns_of), and the machine's parameters at most.
void check_plan_size(const Machine& m, const ProbingPlan& plan, const std::string& option) {
  double unknowns = static_cast<double>(m.parameter_count()) + 1;
  for (const auto& f : plan.features) unknowns += static_cast<double>(unknowns_of(f.kind));
  const double residuals = static_cast<double>(plan.residual_count());
  // Jacobian, Ceres' dense QR copy, the SVD's U (thin) and V: about 4 residuals x unknowns doubles.
  check_estimate({option + " " + plan.source + " (" + std::to_string(plan.records.size()) + " records, " +
                      std::to_string(plan.features.size()) + " features)",
                  4 * 8 * residuals * unknowns, 0, 0});
}

// Configurations per second and thread of the exact model: 2.0e6 measured with `eval --grid` of
// 5e5 points on hu40t-wCBXfYZt, --threads 1 (docs/reliability.md); the time estimates divide by it.
constexpr double kEvaluationsPerSecond = 2e6;
// Subsets per second and thread of identifiability --choose: 1.5e5 measured (C(24, 6) = 134,596
// subsets of the first 24 parameters of hu40t on its SAMBA/TANGO plan in 0.91 s, --threads 1),
// rounded down.
constexpr double kSubsetsPerSecond = 1e5;

void print_names(const char* label, const std::vector<std::string>& names) {
  if (names.empty()) return;
  std::cout << label;
  for (const auto& n : names) std::cout << " " << n;
  std::cout << "\n";
}

void print_identifiability(const Identifiability& id) {
  std::cout << fmt::format(
      "unknowns {} (machine parameters and the artefact's), rank {}; condition {} (all), {:.4g} "
      "(the identifiable ones)\n",
      id.columns.size(), id.rank,
      std::isfinite(id.condition) ? fmt::format("{:.4g}", id.condition) : std::string("infinite"),
      id.condition_identifiable);
  print_names("identifiable:", id.identifiable);
  print_names("NOT identifiable (excluded):", id.unidentifiable);
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
  check_plan_size(m, plan, "--plan");
  SimulationOptions so;
  so.noise = o.noise_um * 1e-3;
  so.artefact_error = o.artefact_um * 1e-3;
  so.seed = o.seed;
  for (const auto& s : o.scale_bars) so.scale_bars.push_back(parse_scale_bar(s, "--scale-bar"));
  if (!o.out.empty()) AtomicFile check(o.out);
  const Simulation sim = simulate_probing(m, plan, so);
  if (!o.out.empty())
    write_probing_csv(
        o.out, m, sim.measurements,
        fmt::format("Simulated by mtcal simulate: machine {}, plan {}, noise {:g} um, artefact error {:g} um, seed {}",
                    o.model.machine, o.plan, o.noise_um, o.artefact_um, o.seed));
  if (o.json_out) {
    print_json(to_json(sim, o.noise_um, o.artefact_um, o.seed, o.out));
    return 0;
  }
  std::cout << fmt::format(
      "simulated {} probings ({} balls and facets) of {} on {}; noise {:g} um, artefact error {:g} um, seed {}\n",
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
  bool json_out = false, require_fit = false;
};

void print_estimates(const IdentificationRun& run) {
  const IdentificationResult& r = run.result;
  const auto& mc = run.monte_carlo;
  const bool truth = run.deviation.has_value();  // an imposed machine was given
  std::cout << fmt::format("{:<10} {:>14} {:>12} {:<8}{}{}\n", "parameter", "value", "u", "unit",
                           mc ? "   u (Monte Carlo)" : "", truth ? "      imposed" : "");
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const auto& p = r.parameters[i];
    std::cout << fmt::format("{:<10} {:>14.6g} {:>12.3g} {:<8}", p.name, p.value, p.u, p.unit);
    if (mc) std::cout << fmt::format(" {:>17.3g}", mc->stdev[i]);
    if (truth) std::cout << fmt::format(" {:>12.6g}", run.imposed[i]);
    std::cout << "\n";
  }
}

void print_identification(const IdentifyOptions& o, const IdentificationRun& run) {
  const IdentificationResult& r = run.result;
  const auto& mc = run.monte_carlo;
  std::cout << fmt::format("{} residuals, {} unknowns, rank {}, condition {:.4g}; {} in {} iterations ({:.1f} ms)\n",
                           r.residuals, r.unknowns, r.identifiability.rank, r.identifiability.condition,
                           r.converged ? "converged" : "NOT converged", r.iterations, run.seconds * 1e3);
  std::string instruments;
  for (const auto kind : {ProbeFeature::Kind::Ballbar, ProbeFeature::Kind::Laser})
    if (std::any_of(run.features.begin(), run.features.end(), [&](const ProbeFeature& f) { return f.kind == kind; }))
      instruments += fmt::format(", {} {:.3f} um", kind == ProbeFeature::Kind::Ballbar ? "ballbars" : "lasers",
                                 (kind == ProbeFeature::Kind::Ballbar ? r.rms_ballbar : r.rms_laser) * 1e3);
  std::cout << fmt::format("residual rms: balls {:.3f} um, facets {:.3f} um, scale bars {:.3f} um{}; sigma0 {:.3g}\n",
                           r.rms_ball * 1e3, r.rms_facet * 1e3, r.rms_scale_bar * 1e3, instruments, r.sigma0);
  const FitCheck fit = check_fit(r);
  std::cout << fmt::format("fit: {} (sigma0 {:.3g}, bound {:.3g} at {:g} %, {} degrees of freedom)\n",
                           fit.poor ? "POOR" : "consistent with the readings' sigma", fit.sigma0, fit.bound,
                           fit.probability * 100, fit.degrees_of_freedom);
  print_estimates(run);
  for (const auto& u : r.identifiability.unidentifiable) std::cout << "NOT identifiable, excluded: " << u << "\n";
  for (const auto& d : r.identifiability.null_directions) std::cout << "  cannot be separated: " << d << "\n";
  if (r.pretravel_estimated)
    std::cout << fmt::format("pre-travel {:.4f} um +- {:.4f}\n", r.pretravel * 1e3, r.pretravel_u * 1e3);
  if (mc)
    std::cout << fmt::format("Monte Carlo: {} runs ({} failed) in {:.2f} s\n", mc->runs, mc->failed,
                             run.monte_carlo_seconds);
  if (run.va) {
    std::cout << fmt::format("VA of the identified model over {}: {:.3f} um", o.workspace, *run.va * 1e3);
    if (mc)
      std::cout << fmt::format(" (Monte Carlo {:.3f} +- {:.3f} um; error map's largest standard deviation {:.3f} um)",
                               mc->va_mean * 1e3, mc->va_stdev * 1e3, mc->map_stdev_max * 1e3);
    std::cout << "\n";
  }
  if (run.deviation)
    std::cout << fmt::format("e_V against {}: max {:.4f} um, rms {:.4f} um\n", o.truth, run.deviation->max * 1e3,
                             run.deviation->rms * 1e3);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_identify(const IdentifyOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.measurements);
  inputs.push_back(o.truth);
  check_outputs(inputs, {o.out, o.report});
  const Machine prior = load(o.model);
  const ProbingPlan meas = read_probing_csv(prior, o.measurements);
  check_plan_size(prior, meas, "--measurements");
  IdentificationOptions opt = to_options(o.est);
  opt.loss = o.loss == "huber"    ? IdentificationOptions::Loss::Huber
             : o.loss == "cauchy" ? IdentificationOptions::Loss::Cauchy
                                  : IdentificationOptions::Loss::None;
  std::optional<Machine> truth;
  if (!o.truth.empty()) truth = load_machine(o.truth);
  AssessmentOptions ao;
  if (!o.workspace.empty()) ao.workspace = checked_grid(prior, o.workspace, false, 2'000'000);
  if ((truth || o.monte_carlo > 0) && ao.workspace.empty() && !o.truth.empty())
    throw InputError({"--truth", 0, ""}, "--truth needs --workspace (the grid over which the models are compared)");
  for (const auto* p : {&o.out, &o.report})
    if (!p->empty()) AtomicFile check(*p);
  {
    // Monte Carlo: every run keeps its model's error map over the workspace (3 doubles a point)
    // and evaluates it; the identification itself is the plan's cost, checked above.
    double points = ao.workspace.empty() ? 0 : 1;
    for (const auto& axis : ao.workspace) points *= static_cast<double>(axis.size());
    const double runs = static_cast<double>(o.monte_carlo);
    const double threads = static_cast<double>(worker_count(o.threads, std::max<std::size_t>(o.monte_carlo, 1)));
    check_estimate({fmt::format("--monte-carlo {} over --workspace of {:.3g} points", o.monte_carlo, points),
                    runs * points * 24, runs * points / kEvaluationsPerSecond / threads, 0});
  }
  Progress progress("Monte Carlo runs", o.monte_carlo);
  if (progress.active()) ao.monte_carlo_progress = [&](std::size_t done, std::size_t) { progress.update(done); };
  ao.monte_carlo_runs = o.monte_carlo;
  ao.seed = o.seed;
  ao.threads = o.threads;
  ao.truth = truth ? &*truth : nullptr;
  const IdentificationRun run = identify_and_assess(prior, meas, opt, ao);
  const FitCheck fit = check_fit(run.result);
  if (fit.poor) {
    const std::string why = poor_fit_message(fit);
    if (o.require_fit) throw InputError({o.measurements, 0, ""}, why + "; nothing written (--require-fit)");
    std::cerr << "mtcal: warning: " << why << "\n";
  }
  if (!o.out.empty()) write_identified_parameters(o.out, prior, run.result, o.measurements);
  if (!o.report.empty())
    identification_report(prior, run, {o.model.params, o.measurements, o.truth, o.workspace}, command_line())
        .write(o.report);
  if (recording()) {
    // The measurements and options the report is made from again (docs/history.md "Measurement
    // files"); what the store does not keep is named, and such a record has no report from it.
    std::vector<std::string> not_kept;
    if (!o.model.set.empty()) not_kept.push_back("--set");
    if (!o.model.only.empty()) not_kept.push_back("--only");
    if (o.model.tool_length) not_kept.push_back("--tool-length");
    if (!o.truth.empty()) not_kept.push_back("--truth");
    if (!o.workspace.empty()) not_kept.push_back("--workspace");
    if (o.monte_carlo > 0) not_kept.push_back("--monte-carlo");
    note_report_source(o.measurements,
                       identification_invocation(command_line(), o.measurements, o.model.machine, o.model.params,
                                                 o.est.estimate, o.est.scale_bars, o.est.pretravel, o.est.sigma_um,
                                                 o.est.rank_tolerance, o.loss, not_kept, session_metadata()));
  }
  if ((o.json_out || recording()) && emit_json(to_json(run, o.out, o.report), o.json_out)) return 0;
  print_identification(o, run);
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

SubsetOptions subset_options(const IdentifiabilityOptions& o) {
  SubsetOptions so;
  so.candidates = o.candidates;
  so.always = o.always;
  so.choose = o.choose;
  so.threads = o.threads;
  so.rank_tolerance = std::max(o.est.rank_tolerance, 1e-7);  // the normal matrix resolves no finer
  so.keep = o.list;
  so.by_residue = o.sort == "residue";
  so.candidates_source = "--candidates";
  so.always_source = "--always";
  so.choose_source = "--choose";
  so.by_residue_source = "--sort";
  so.rank_tolerance_source = "--rank-tolerance";
  return so;
}

void print_subsets(const SubsetAnalysis& a, std::size_t choose, double seconds) {
  const std::vector<std::string>& names = a.candidates;  // resolved: errors expanded, duplicates removed
  std::cout << fmt::format(
      "{} of the {} subsets of {} among {} candidates give a full-rank model ({:.3f} s, {} partial subsets pruned)\n",
      a.full_rank, a.examined, choose, names.size(), seconds, a.pruned);
  for (const auto& s : a.subsets) {
    std::string line = fmt::format("  cond {:>10.4g}", s.condition);
    if (!std::isnan(s.residue)) line += fmt::format("  residue {:.4g}", s.residue);
    line += " :";
    for (std::size_t i : s.members) line += " " + (i < names.size() ? names[i] : std::to_string(i));
    std::cout << line << "\n";
  }
  if (a.full_rank > a.subsets.size())
    std::cout << fmt::format("  ... {} more (--list)\n", a.full_rank - a.subsets.size());
}

int run_identifiability(const IdentifiabilityOptions& o) {
  const Machine m = load(o.model);
  const ProbingPlan plan = read_probing_csv(m, o.plan);
  check_plan_size(m, plan, "--plan");
  IdentificationOptions opt = to_options(o.est);
  if (o.choose == 0) {
    if (o.est.estimate.empty())
      throw InputError({"--estimate", 0, ""}, "expected --estimate, or --candidates with --choose");
    const Identifiability id = identifiability(m, plan, opt);
    if (o.json_out)
      print_json(to_json(id));
    else
      print_identifiability(id);
    return 0;
  }
  if (o.candidates.empty()) throw InputError({"--candidates", 0, ""}, "--choose needs --candidates");
  SubsetOptions so = subset_options(o);
  // C(n, k) subsets could take longer than the universe: refused above what --max-time allows.
  so.max_subsets =
      static_cast<std::uint64_t>(std::min(1e19, run_limits().seconds * kSubsetsPerSecond *
                                                    static_cast<double>(worker_count(o.threads, 1u << 20))));
  Progress progress("subsets", 1);
  if (progress.active()) so.progress = [&](std::size_t done, std::size_t total) { progress.update(done, total); };
  const auto t0 = Clock::now();
  const SubsetAnalysis a = full_rank_subsets(m, plan, so, opt);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (o.json_out)
    print_json(to_json(a, so, seconds));
  else
    print_subsets(a, o.choose, seconds);
  return 0;
}

}  // namespace

std::vector<Command> add_identification_commands(CLI::App& app) {
  std::vector<Command> out;
  {
    auto o = std::make_shared<SimulateOptions>();
    auto* c = app.add_subcommand("simulate",
                                 "Virtual machine (Viprey 2015 fig. 4): the readings a machine gives for a probing "
                                 "plan (balls and facets at indexations), with noise and an uncalibrated artefact");
    add_model_options(c, o->model);
    c->add_option("--plan", o->plan, "Probing plan CSV (docs/identification.md)")->required();
    c->add_option("--noise-um", o->noise_um, "Standard deviation of each reading, um")
        ->transform(length_in(1e-3, "LENGTH"))
        ->check(CLI::NonNegativeNumber & kFinite)
        ->capture_default_str();
    c->add_option("--artefact-error-um", o->artefact_um,
                  "Standard deviation of the features' true positions about the plan's, um")
        ->transform(length_in(1e-3, "LENGTH"))
        ->check(CLI::NonNegativeNumber & kFinite)
        ->capture_default_str();
    c->add_option("--seed", o->seed, "Random seed")->capture_default_str();
    c->add_option("--scale-bar", o->scale_bars,
                  "Make two balls exactly this far apart: BALL:BALL:LENGTH (mm); repeatable");
    c->add_option("--out", o->out, "Measurement CSV to write (the plan's columns plus the readings X, Y, Z)");
    c->add_flag("--json", o->json_out, "Machine-readable output: records residuals noise_um seed truth out");
    out.push_back({c, [o] { return run_simulate(*o); }});
  }
  {
    auto o = std::make_shared<IdentifyOptions>();
    auto* c =
        app.add_subcommand("identify",
                           "Identify machine parameters from probing measurements: nonlinear least squares on "
                           "the exact model (Ceres), rank, conditioning, uncertainties, what is not identifiable");
    add_model_options(c, o->model);
    c->add_option("--measurements", o->measurements,
                  "Measurement CSV (docs/identification.md), e.g. from mtcal simulate")
        ->required();
    add_estimate_options(c, o->est, true);
    c->add_option("--loss", o->loss, "Robust loss on each probing: none, huber or cauchy (scale 3 sigma)")
        ->check(CLI::IsMember({"none", "huber", "cauchy"}))
        ->capture_default_str();
    c->add_option("--monte-carlo", o->monte_carlo, "Runs of re-drawn noise for Monte Carlo uncertainties")
        ->check(CLI::Range(0, 1000000));
    c->add_option("--seed", o->seed, "Seed of the Monte Carlo runs")->capture_default_str();
    c->add_option("--workspace", o->workspace,
                  "Grid for the identified model's VA (and its Monte Carlo spread), e.g. "
                  "\"X=-300:300:7,Y=-250:250:7,Z=-300:300:7,B=0:90:3\"");
    c->add_option("--truth", o->truth,
                  "The imposed machine (simulations): e_V, the identified model against it over --workspace");
    c->add_option("--threads", o->threads, "Threads for Monte Carlo (0: all cores)")->check(CLI::Range(0, 1024));
    c->add_option("--out", o->out, "Parameter file with the identified errors (mtcal eval --params ...)");
    c->add_option("--report", o->report, "Write an HTML report");
    c->add_flag("--require-fit", o->require_fit,
                "Refuse a poor fit (sigma0 above its chi-square bound at 99.9 %): exit non-zero, write nothing "
                "(without it: a warning on stderr and fit.poor in --json)");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: parameters{value u} rank condition rms_um unidentifiable ...");
    out.push_back({c, [o] { return run_identify(*o); }});
  }
  {
    auto o = std::make_shared<IdentifiabilityOptions>();
    auto* c = app.add_subcommand("identifiability",
                                 "What a probing plan can identify: rank and singular values of the scaled "
                                 "Jacobian, unidentifiable combinations; or every full-rank subset of K "
                                 "candidate parameters (Viprey 2015)");
    add_model_options(c, o->model);
    c->add_option("--plan", o->plan, "Probing plan or measurement CSV")->required();
    add_estimate_options(c, o->est, false);
    // The subset analysis's options are refused without --choose (they would be ignored silently).
    auto* choose = c->add_option("--choose", o->choose, "Subset size K")->check(CLI::Range(1, 64));
    c->add_option("--candidates", o->candidates, "Candidate parameters for the subset analysis")
        ->delimiter(',')
        ->needs(choose);
    c->add_option("--always", o->always, "Parameters in every subset (e.g. the tool mounting positions)")
        ->delimiter(',')
        ->needs(choose);
    c->add_option("--list", o->list, "Subsets listed, best first")->capture_default_str()->needs(choose);
    c->add_option("--sort", o->sort,
                  "Rank subsets by condition number, or by residue of estimation (measurements only)")
        ->check(CLI::IsMember({"condition", "residue"}))
        ->capture_default_str()
        ->needs(choose);
    c->add_option("--threads", o->threads, "Threads (0: all cores)")->check(CLI::Range(0, 1024));
    c->add_flag("--json", o->json_out,
                "Machine-readable output: rank singular_values unidentifiable ...; with --choose: count "
                "subsets[parameters condition]");
    out.push_back({c, [o] { return run_identifiability(*o); }});
  }
  return out;
}

}  // namespace mtcal::cli
