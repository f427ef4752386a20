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
#include "history.hpp"
#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/identification/machine_params.hpp"
#include "mtcal/io/model/estimated_parameters_file.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/acceptance_json.hpp"
#include "mtcal/io/json/evaluation_json.hpp"
#include "mtcal/io/json/identification_json.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/report/recorded.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

struct Iso2302Options {
  std::string file, unit = "mm", target_unit, report, format = "auto";
  double wrap = 0;
  bool json_out = false;
  ToleranceOptions tol;
};

int run_iso230_2(const Iso2302Options& o) {
  std::vector<std::string> inputs = metadata_inputs();
  inputs.insert(inputs.end(), {o.file, o.tol.file});
  check_outputs(inputs, {o.report});
  PositioningRuns runs = read_positioning_file(o.file, o.format, o.unit, o.target_unit);
  if (o.wrap > 0) runs = merge_wrapped_targets(runs, o.wrap);
  const PositioningEvaluation e = evaluate_positioning(runs);
  // What the file's header states (a laser file's machine, date, temperatures, instrument) fills
  // the report's metadata where --meta and --meta-file left a field empty: the user's word wins.
  const bool user_metadata = !session_metadata().empty();
  if (ReportMetadata from_file = laser_report_metadata(runs); !from_file.empty()) {
    ReportMetadata m = session_metadata();
    m.fill_missing_from(from_file);
    set_session_metadata(std::move(m));
  }
  const std::string* axis = session_metadata().get("axis");
  const Tolerances limits = tolerances_for(o.tol, AcceptanceTest::Iso230_2, axis ? *axis : "");
  const ToleranceVerdict verdict = limits.empty() ? ToleranceVerdict{} : checked_verdict(tolerance_values(e), limits);
  if (!o.report.empty()) write_positioning_report(o.report, command_line(), runs, e, verdict);
  if (recording())
    note_report_source(o.file, positioning_invocation(command_line(), o.file, o.format, o.unit, o.target_unit, o.wrap,
                                                      verdict, session_metadata()));
  // After the work: a failure is one line on stderr, never warnings and then an error.
  for (const auto& w : runs.warnings) std::cerr << "mtcal: warning: " << w << "\n";
  if (o.tol.given() && limits.empty())
    std::cerr << "mtcal: warning: the tolerance file has no iso230-2 entry for axis '" << (axis ? *axis : "")
              << "' nor 'any': nothing checked\n";
  warn_missing_metadata(AcceptanceTest::Iso230_2, !o.report.empty() || o.tol.given() || user_metadata);
  if (o.json_out || recording()) {
    Json j = to_json(e);
    Json meta = Json::object();
    for (const auto& [k, v] : runs.metadata) meta[k] = v;  // a key given twice keeps its last value
    j["metadata"] = meta;                                  // print_json adds the user's --meta/--meta-file fields to it
    j["warnings"] = runs.warnings;
    if (!verdict.empty()) j["tolerances"] = to_json(verdict);
    if (!o.report.empty()) j["report"] = o.report;
    if (emit_json(j, o.json_out)) return verdict_exit_code(o.tol, verdict);
  }
  std::cout << positioning_text(runs, e);
  print_verdict(verdict);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return verdict_exit_code(o.tol, verdict);
}

struct BallbarCliOptions {
  std::string trace, plane = "XY", direction, report, out, centre, to_params, terms = "squareness,scale,backlash";
  ModelOptions model;
  double radius = 0, feed = 0, overshoot_start = 0, overshoot_stop = 0, step_deg = 1;
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

BallbarOptions ballbar_options(const BallbarCliOptions& o) {
  BallbarOptions bo;
  bo.nominal_radius = o.radius;
  bo.overshoot_start = o.overshoot_start;
  bo.overshoot_stop = o.overshoot_stop;
  if (o.direction == "cw") bo.only = CircleDirection::CW;
  if (o.direction == "ccw") bo.only = CircleDirection::CCW;
  return bo;
}

// --to-params and --terms: which machine parameters the trace's diagnosis gives.
BallbarParamsOptions ballbar_params_options(const BallbarCliOptions& o, const BallbarOptions& bo) {
  BallbarParamsOptions po{false, false, false};
  if (o.to_params.empty()) return po;
  if (bo.only) throw InputError({"--to-params", 0, ""}, "--to-params needs both directions (not with --direction)");
  for (const auto& term : split_list(o.terms)) {
    if (term == "squareness")
      po.squareness = true;
    else if (term == "scale")
      po.scale = true;
    else if (term == "backlash")
      po.backlash = true;
    else
      throw InputError({"--terms", 0, ""}, "expected squareness, scale or backlash, found '" + term + "'");
  }
  AtomicFile check(o.to_params);  // refuse a bad path before the work
  return po;
}

void write_ballbar_parameters(const BallbarCliOptions& o, const std::vector<EstimatedError>& params) {
  write_estimated_parameters(o.to_params, params,
                             fmt::format("Squareness, scale and reversal of the {} plane from a ballbar trace (mtcal "
                                         "ballbar --to-params; internal units mm, rad)\n{}",
                                         o.plane, command_line()));
}

void print_ballbar_results(const BallbarCliOptions& o, const BallbarEvaluation& e,
                           const std::optional<TraceDiagnosis>& diagnosis, const ToleranceVerdict& verdict,
                           const std::vector<EstimatedError>& params) {
  print_ballbar(o, e, diagnosis);
  print_verdict(verdict);
  for (const auto& p : params) std::cout << fmt::format("parameter {}: {}\n", p.name.str(), p.method);
  if (!o.to_params.empty()) std::cout << "wrote " << o.to_params << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_ballbar(const BallbarCliOptions& o) {
  // The bar's length defines the test: no default that could silently differ from the one used.
  if (o.radius <= 0)
    throw InputError({"--radius", 0, ""},
                     "expected the nominal radius of the test (the ballbar's length, e.g. "
                     "--radius 150 or --radius 150mm); it has no default");
  if (o.predict) return run_ballbar_predict(o);
  if (o.trace.empty()) throw InputError({"ballbar", 0, ""}, "expected a trace file (or --predict)");
  std::vector<std::string> inputs = metadata_inputs();
  inputs.insert(inputs.end(), {o.trace, o.tol.file});
  check_outputs(inputs, {o.report, o.to_params});
  const BallbarOptions bo = ballbar_options(o);
  const BallbarParamsOptions po = ballbar_params_options(o, bo);
  const BallbarTrace t = read_ballbar_csv(o.trace);
  check_directions(t, bo);
  const auto e = evaluate_ballbar(t, bo);
  std::optional<TraceDiagnosis> diagnosis;
  if (!bo.only) diagnosis = diagnose_ballbar(t, bo, o.plane);
  const Tolerances limits = tolerances_for(o.tol, AcceptanceTest::Iso230_4);
  const ToleranceVerdict verdict = limits.empty() ? ToleranceVerdict{} : checked_verdict(tolerance_values(e), limits);
  if (o.feed > 0 && !session_metadata().get("feed")) {
    ReportMetadata m = session_metadata();
    m.set("feed", fmt::format("{:g} mm/min", o.feed));
    set_session_metadata(std::move(m));
  }
  std::vector<EstimatedError> params;
  if (!o.to_params.empty()) {
    params = ballbar_parameters(*diagnosis, o.plane, po, t.source);
    write_ballbar_parameters(o, params);
  }
  if (!o.report.empty())
    write_ballbar_report(o.report, command_line(), t, e, diagnosis, o.plane, o.radius, o.feed, verdict);
  if (recording())
    note_report_source(o.trace, ballbar_invocation(command_line(), o.trace, o.plane, o.radius, o.feed, o.overshoot_start,
                                                   o.overshoot_stop, o.direction, verdict, session_metadata()));
  warn_missing_metadata(AcceptanceTest::Iso230_4, !o.report.empty() || o.tol.given());
  if (o.json_out || recording()) {
    Json j = to_json(e, diagnosis, o.plane, o.radius, o.feed);
    if (!verdict.empty()) j["tolerances"] = to_json(verdict);
    if (!o.report.empty()) j["report"] = o.report;
    if (!o.to_params.empty()) {
      j["parameters"] = estimated_parameters_json(params);
      j["to_params"] = o.to_params;
    }
    if (emit_json(j, o.json_out)) return verdict_exit_code(o.tol, verdict);
  }
  print_ballbar_results(o, e, diagnosis, verdict, params);
  return verdict_exit_code(o.tol, verdict);
}

}  // namespace

std::vector<Command> add_evaluation_commands(CLI::App& app) {
  auto o = std::make_shared<Iso2302Options>();
  auto* c = app.add_subcommand("iso230-2",
                               "ISO 230-2 linear positioning: accuracy A, repeatability R, reversal B, "
                               "systematic and mean positioning errors E and M, per target and per axis");
  c->add_option("file", o->file,
                "Measurements: a table (CSV/TSV, ';' ',' or tab, headers such as target,run,direction,measured "
                "or target,direction,deviation), the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], "
                "REF_DATA_BWD[i,j], UNIT), or a Renishaw LaserXL/CARTO .rtl/.rta export")
      ->required();
  c->add_option("--unit", o->unit, "Unit of a table's values unless its header says ('deviation [um]')")
      ->check(kUnitName)
      ->capture_default_str();
  c->add_option("--target-unit", o->target_unit, "Unit of a table's targets (default: the values' unit)")
      ->check(kUnitName);
  c->add_option("--format", o->format, "Input format: auto (by extension or content), csv, dat or laser")
      ->check(CLI::IsMember({"auto", "csv", "dat", "laser"}))
      ->capture_default_str();
  c->add_option("--wrap", o->wrap,
                "Rotary test: targets one turn apart (this many target units, e.g. 360) are one position "
                "of the axis; their runs are pooled")
      ->check(CLI::PositiveNumber & kFinite);
  c->add_flag("--json", o->json_out,
              "Machine-readable output, full precision: A A_up A_down B B_mean R R_up R_down E E_up E_down M at "
              "the top level (input unit; null where the test does not define them), per-target values under "
              "targets, notes, metadata, warnings");
  c->add_option("--report", o->report,
                "Write an HTML report (µm): results A, E, M, R, B, deviations with ±2s bands per direction and "
                "the results marked, the per-target table in ISO 230-2's layout");
  add_tolerance_options(c, o->tol, "A, E, M, R, B (bidirectional; a tolerance file picks the entry of --meta axis=)");
  c->footer(
      "Examples:\n  mtcal iso230-2 examples/data/iso230-2-x-axis.csv\n"
      "  mtcal iso230-2 examples/data/iso230-2-x-axis.csv --unit mm --json\n"
      "  mtcal iso230-2 examples/instruments/x-axis.rtl --report x.html\n"
      "Other forms: mtcal iso230-2 x_axis.dat; runs.csv --unit um --target-unit mm; c_axis.rta --wrap 360");
  auto b = std::make_shared<BallbarCliOptions>();
  auto* bb = app.add_subcommand("ballbar",
                                "ISO 230-4 circular test: G per direction (least-squares and minimum-zone "
                                "centres), G(b), H, F from a ballbar trace; or --predict the trace of a "
                                "machine model");
  bb->add_option("trace", b->trace, "Trace CSV direction,angle_deg,radius_mm (direction cw or ccw)");
  bb->add_option("--radius", b->radius,
                 "Nominal radius (the ballbar's length), mm or with a unit: 150, 150mm, 6in; required")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(CLI::PositiveNumber & kFinite);
  bb->add_option("--plane", b->plane, "Test plane: XY, YZ or ZX")
      ->check(CLI::IsMember({"XY", "YZ", "ZX"}))
      ->capture_default_str();
  bb->add_option("--feed", b->feed, "Feed, mm/min (recorded in the output)")->check(kFinite);
  bb->add_option("--overshoot-start", b->overshoot_start, "Degrees of travel ignored after each direction's start")
      ->transform(angle_in(std::numbers::pi / 180, "ANGLE"))
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--overshoot-stop", b->overshoot_stop, "Degrees of travel ignored before each direction's end")
      ->transform(angle_in(std::numbers::pi / 180, "ANGLE"))
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--direction", b->direction, "Evaluate one direction only: cw or ccw (no G(b), no H)")
      ->check(CLI::IsMember({"cw", "ccw"}));
  bb->add_flag("--json", b->json_out,
               "Machine-readable output: G_cw G_ccw G_b H F_max F_min F_mean_bidirectional "
               "(mm), per direction under cw and ccw");
  bb->add_option("--report", b->report,
                 "Write an HTML report: recording conditions, polar plot of both directions, ISO 230-4 table");
  add_tolerance_options(bb, b->tol, "G (G(b) with both directions), F (larger of |F max|, |F min|), H");
  // The prediction's options are refused without --predict (they would be ignored silently).
  auto* predict = bb->add_flag("--predict", b->predict, "Predict the trace of --machine instead of evaluating one");
  bb->add_option("--machine,-m", b->model.machine, "Machine file, with --predict")->needs(predict);
  bb->add_option("--params", b->model.params, "Parameter files applied to the machine, with --predict")->needs(predict);
  bb->add_option("--centre", b->centre, "Centre of the circle as joint values, e.g. \"X=0,Y=0,Z=-100\" (mm, deg)")
      ->needs(predict);
  bb->add_option("--step-deg", b->step_deg, "Angle between predicted samples, deg")
      ->transform(angle_in(std::numbers::pi / 180, "ANGLE"))
      ->check(CLI::Range(0.01, 10.0) & kFinite)
      ->needs(predict);
  bb->add_option("--out", b->out, "Trace CSV to write, with --predict")->needs(predict);
  bb->add_option("--to-params", b->to_params,
                 "Write the diagnostics as a parameter file (--params): squareness (EC0Y for XY, EA0Z for YZ, "
                 "EB0Z for ZX), scale mismatch and backlash as the two axes' positioning errors");
  bb->add_option("--terms", b->terms, "With --to-params: which of squareness, scale, backlash")->capture_default_str();
  bb->footer(
      "Examples:\n  mtcal ballbar trace.csv --radius 150 --plane XY\n"
      "  mtcal ballbar trace.csv --radius 150 --to-params xy.yaml --terms squareness\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --params xy.yaml --format klipper --out skew.cfg");
  return {{c, [o] { return run_iso230_2(*o); }}, {bb, [b] { return run_ballbar(*b); }}};
}

}  // namespace mtcal::cli
