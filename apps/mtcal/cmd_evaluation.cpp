// mtcal iso230-2 and ballbar: ISO 230-2 positioning of a linear axis, ISO 230-4 circular tests.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/evaluation_files.hpp"
#include "mtcal/io/evaluation_json.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

struct Iso2302Options {
  std::string file, unit = "mm", report, format = "auto";
  bool json_out = false;
  ToleranceOptions tol;
};

// The quantities of an ISO 230-2 evaluation in µm, for tolerances.
std::vector<std::pair<std::string, double>> positioning_values(const PositioningEvaluation& e) {
  const auto k = micrometres_per(e.unit);
  if (!k)
    throw InputError({e.unit, 0, ""}, "tolerances are in µm; the measurements' unit '" + e.unit +
                                          "' is not a known length unit (mm, um, nm, m, in)");
  return {{"A", e.A * *k}, {"E", e.E * *k}, {"M", e.M * *k}, {"R", e.R * *k}, {"B", e.B * *k}};
}

void print_positioning(const PositioningEvaluation& e) {
  std::cout << fmt::format("ISO 230-2: {} targets x {} runs per direction, unit {}\n", e.targets.size(), e.runs,
                           e.unit);
  std::cout << fmt::format("{:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "target", "mean_up",
                           "mean_down", "B_i", "s_up", "s_down", "R_i", "mean");
  for (const auto& t : e.targets)
    std::cout << fmt::format("{:>10g} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f}\n",
                             t.target, t.mean_up, t.mean_down, t.reversal, t.s_up, t.s_down, t.R, t.mean);
  std::cout << fmt::format("A {:.5f} (up {:.5f}, down {:.5f})   R {:.5f} (up {:.5f}, down {:.5f})\n", e.A, e.A_up,
                           e.A_down, e.R, e.R_up, e.R_down);
  std::cout << fmt::format("B {:.5f} (mean {:.5f})   E {:.5f} (up {:.5f}, down {:.5f})   M {:.5f}   [{}]\n", e.B,
                           e.B_mean, e.E, e.E_up, e.E_down, e.M, e.unit);
}

int run_iso230_2(const Iso2302Options& o) {
  std::vector<std::string> inputs = metadata_inputs();
  inputs.insert(inputs.end(), {o.file, o.tol.file});
  check_outputs(inputs, {o.report});
  const PositioningRuns runs = read_positioning_file(o.file, o.format, o.unit);
  const PositioningEvaluation e = evaluate_positioning(runs);
  const std::string* axis = session_metadata().get("axis");
  const Tolerances limits = tolerances_for(o.tol, AcceptanceTest::Iso230_2, axis ? *axis : "");
  const ToleranceVerdict verdict = limits.empty() ? ToleranceVerdict{} : checked_verdict(positioning_values(e), limits);
  if (o.tol.given() && limits.empty())
    std::cerr << "mtcal: warning: the tolerance file has no iso230-2 entry for axis '" << (axis ? *axis : "")
              << "' nor 'any': nothing checked\n";
  if (!o.report.empty()) write_positioning_report(o.report, command_line(), runs, e, verdict);
  // After the work, so that a failing run says one thing: its error.
  warn_missing_metadata(AcceptanceTest::Iso230_2, !o.report.empty() || o.tol.given());
  if (o.json_out) {
    Json j = to_json(e);
    if (!verdict.empty()) j["tolerances"] = to_json(verdict);
    if (!o.report.empty()) j["report"] = o.report;
    print_json(j);
    return verdict_exit_code(o.tol, verdict);
  }
  print_positioning(e);
  print_verdict(verdict);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return verdict_exit_code(o.tol, verdict);
}

struct BallbarCliOptions {
  std::string trace, plane = "XY", direction, report, out, centre;
  ModelOptions model;
  double radius = 150, feed = 0, overshoot_start = 0, overshoot_stop = 0, step_deg = 1;
  bool predict = false, json_out = false;
  ToleranceOptions tol;
};

int run_ballbar_predict(const BallbarCliOptions& o) {
  if (o.model.machine.empty() || o.out.empty())
    throw InputError({"--predict", 0, ""}, "--predict needs --machine and --out");
  check_outputs(model_inputs(o.model), {o.out});
  const Machine m = load(o.model);
  const auto centre = parse_joint_values(m, o.centre, "--centre");
  const auto t = [&] {
    try {
      return predict_ballbar(m, o.plane, centre, o.radius, o.step_deg * std::numbers::pi / 180);
    } catch (const InputError& e) {
      rethrow_for_options(e, {{"centre", "--centre"}});
    }
  }();
  write_ballbar_csv(o.out, t);
  std::cout << fmt::format("predicted {} samples of a {} mm circle in {} on {}: wrote {}\n", t.size(), o.radius,
                           o.plane, m.name, o.out);
  return 0;
}

// A one-direction trace without --direction: the library refuses it for G(b) and H; the CLI names
// the option that evaluates one direction.
void check_directions(const BallbarTrace& t, const BallbarOptions& bo) {
  if (bo.only) return;
  auto has = [&](CircleDirection d) {
    return std::any_of(t.points.begin(), t.points.end(), [&](const TracePoint& p) { return p.direction == d; });
  };
  const bool cw = has(CircleDirection::CW), ccw = has(CircleDirection::CCW);
  if (cw != ccw)
    throw InputError({t.source, 0, ""},
                     fmt::format("G(b) and H need both directions; the trace has only {} samples (use "
                                 "--direction to evaluate one)",
                                 cw ? "cw" : "ccw"));
}

void print_ballbar(const BallbarCliOptions& o, const BallbarEvaluation& e,
                   const std::optional<TraceDiagnosis>& diagnosis) {
  std::cout << fmt::format("ISO 230-4 circular test, plane {}, radius {:g} mm{}\n", o.plane, o.radius,
                           o.feed > 0 ? fmt::format(", feed {:g} mm/min", o.feed) : std::string());
  for (const auto& [name, d] : {std::pair{"CW ", e.cw}, std::pair{"CCW", e.ccw}})
    if (d)
      std::cout << fmt::format("{}  G {:.2f} um (minimum zone {:.2f})  F max {:.2f} min {:.2f} um  ({} samples)\n",
                               name, d->G * 1e3, d->G_minimum_zone * 1e3, d->F_max * 1e3, d->F_min * 1e3, d->points);
  if (e.G_b)
    std::cout << fmt::format("G(b) {:.2f} um   H {:.2f} um   mean radial deviation {:.2f} um\n", *e.G_b * 1e3,
                             *e.H * 1e3, *e.F_mean_bidirectional * 1e3);
  if (diagnosis) {
    std::cout << "diagnostics (least-squares fit of the trace model; share of the fitted trace):\n";
    for (const auto& term : diagnosis->terms)
      std::cout << fmt::format("  {:<34} {:>9.3f} +- {:<7.3f} {:<5} {:>5.1f} %\n", term.name, term.value,
                               term.uncertainty, term.unit, term.share);
    std::cout << fmt::format("  residual rms {:.3f} um\n", diagnosis->residual_rms);
  }
}

int run_ballbar(const BallbarCliOptions& o) {
  if (o.predict) return run_ballbar_predict(o);
  if (o.trace.empty()) throw InputError({"ballbar", 0, ""}, "expected a trace file (or --predict)");
  std::vector<std::string> inputs = metadata_inputs();
  inputs.insert(inputs.end(), {o.trace, o.tol.file});
  check_outputs(inputs, {o.report});
  BallbarOptions bo;
  bo.nominal_radius = o.radius;
  bo.overshoot_start = o.overshoot_start;
  bo.overshoot_stop = o.overshoot_stop;
  if (o.direction == "cw") bo.only = CircleDirection::CW;
  if (o.direction == "ccw") bo.only = CircleDirection::CCW;
  const BallbarTrace t = read_ballbar_csv(o.trace);
  check_directions(t, bo);
  const auto e = evaluate_ballbar(t, bo);
  std::optional<TraceDiagnosis> diagnosis;
  if (!bo.only) diagnosis = diagnose_ballbar(t, bo, o.plane);
  // ISO 230-4 quantities in µm: G is G(b) when both directions were run, else the one direction's
  // G; F is the larger magnitude of F max and F min; H the hysteresis.
  std::vector<std::pair<std::string, double>> values;
  if (e.G_b)
    values.emplace_back("G", *e.G_b * 1e3);
  else if (e.cw || e.ccw)
    values.emplace_back("G", (e.cw ? e.cw->G : e.ccw->G) * 1e3);
  values.emplace_back("F", std::max(std::abs(e.F_max), std::abs(e.F_min)) * 1e3);
  if (e.H) values.emplace_back("H", *e.H * 1e3);
  const Tolerances limits = tolerances_for(o.tol, AcceptanceTest::Iso230_4);
  const ToleranceVerdict verdict = limits.empty() ? ToleranceVerdict{} : checked_verdict(values, limits);
  if (o.feed > 0 && !session_metadata().get("feed")) {
    ReportMetadata m = session_metadata();
    m.set("feed", fmt::format("{:g} mm/min", o.feed));
    set_session_metadata(std::move(m));
  }
  if (!o.report.empty())
    write_ballbar_report(o.report, command_line(), t, e, diagnosis, o.plane, o.radius, o.feed, verdict);
  warn_missing_metadata(AcceptanceTest::Iso230_4, !o.report.empty() || o.tol.given());
  if (o.json_out) {
    Json j = to_json(e, diagnosis, o.plane, o.radius, o.feed);
    if (!verdict.empty()) j["tolerances"] = to_json(verdict);
    if (!o.report.empty()) j["report"] = o.report;
    print_json(j);
    return verdict_exit_code(o.tol, verdict);
  }
  print_ballbar(o, e, diagnosis);
  print_verdict(verdict);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return verdict_exit_code(o.tol, verdict);
}

}  // namespace

std::vector<Command> add_evaluation_commands(CLI::App& app) {
  auto o = std::make_shared<Iso2302Options>();
  auto* c = app.add_subcommand("iso230-2",
                               "ISO 230-2 linear positioning: accuracy A, repeatability R, reversal B, "
                               "systematic and mean positioning errors E and M, per target and per axis");
  c->add_option("file", o->file,
                "Measurements: CSV target,run,direction,measured (direction up/down or +/-), or "
                "the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT)")
      ->required();
  c->add_option("--unit", o->unit, "Unit of a CSV's values (a .dat file says its own)")->capture_default_str();
  c->add_option("--format", o->format, "Input format: auto (by .dat extension or content), csv or dat")
      ->check(CLI::IsMember({"auto", "csv", "dat"}))
      ->capture_default_str();
  c->add_flag("--json", o->json_out,
              "Machine-readable output: A A_up A_down B B_mean R R_up R_down E E_up E_down M at "
              "the top level (input unit), per-target values under targets");
  c->add_option("--report", o->report,
                "Write an HTML report (µm): results A, E, M, R, B, deviations with ±2s bands per direction and "
                "the results marked, the per-target table in ISO 230-2's layout");
  add_tolerance_options(c, o->tol, "A, E, M, R, B (bidirectional; a tolerance file picks the entry of --meta axis=)");
  auto b = std::make_shared<BallbarCliOptions>();
  auto* bb = app.add_subcommand("ballbar",
                                "ISO 230-4 circular test: G per direction (least-squares and minimum-zone "
                                "centres), G(b), H, F from a ballbar trace; or --predict the trace of a "
                                "machine model");
  bb->add_option("trace", b->trace, "Trace CSV direction,angle_deg,radius_mm (direction cw or ccw)");
  bb->add_option("--radius", b->radius, "Nominal radius, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  bb->add_option("--plane", b->plane, "Test plane: XY, YZ or ZX")
      ->check(CLI::IsMember({"XY", "YZ", "ZX"}))
      ->capture_default_str();
  bb->add_option("--feed", b->feed, "Feed, mm/min (recorded in the output)")->check(kFinite);
  bb->add_option("--overshoot-start", b->overshoot_start, "Degrees of travel ignored after each direction's start")
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--overshoot-stop", b->overshoot_stop, "Degrees of travel ignored before each direction's end")
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--direction", b->direction, "Evaluate one direction only: cw or ccw (no G(b), no H)")
      ->check(CLI::IsMember({"cw", "ccw"}));
  bb->add_flag("--json", b->json_out,
               "Machine-readable output: G_cw G_ccw G_b H F_max F_min F_mean_bidirectional "
               "(mm), per direction under cw and ccw");
  bb->add_option("--report", b->report,
                 "Write an HTML report: recording conditions, polar plot of both directions, ISO 230-4 table");
  add_tolerance_options(bb, b->tol, "G (G(b) with both directions), F (larger of |F max|, |F min|), H");
  bb->add_flag("--predict", b->predict, "Predict the trace of --machine instead of evaluating one");
  bb->add_option("--machine,-m", b->model.machine, "Machine file, with --predict");
  bb->add_option("--params", b->model.params, "Parameter files applied to the machine, with --predict");
  bb->add_option("--centre", b->centre, "Centre of the circle as joint values, e.g. \"X=0,Y=0,Z=-100\" (mm, deg)");
  bb->add_option("--step-deg", b->step_deg, "Angle between predicted samples, deg")
      ->check(CLI::Range(0.01, 10.0) & kFinite);
  bb->add_option("--out", b->out, "Trace CSV to write, with --predict");
  return {{c, [o] { return run_iso230_2(*o); }}, {bb, [b] { return run_ballbar(*b); }}};
}

}  // namespace mtcal::cli
