// mtcal iso230-2: ISO 230-2 positioning accuracy and repeatability of a linear axis.
#include <iostream>
#include <cmath>
#include <memory>
#include <optional>
#include <numbers>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/io/machine_file.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;

struct Iso2302Options {
  std::string file, unit = "mm", report, format = "auto";
  bool json_out = false;
};

bool looks_like_dat(const std::string& path) {
  if (path.size() >= 4 && path.substr(path.size() - 4) == ".dat") return true;
  return read_text_file(path, "positioning file").find("TGT_DATA[") != std::string::npos;
}

void write_report(const Iso2302Options& o, const PositioningRuns& runs, const PositioningEvaluation& e) {
  Report r("ISO 230-2 positioning of a linear axis", command_line());
  r.add_input("measurements", o.file);
  const std::string u = e.unit;
  r.add_figure("accuracy A", fmt::format("{:.4f}", e.A), u);
  r.add_figure("repeatability R", fmt::format("{:.4f}", e.R), u);
  r.add_figure("reversal value B", fmt::format("{:.4f}", e.B), u);
  r.add_figure("systematic positioning error E", fmt::format("{:.4f}", e.E), u);
  r.add_figure("mean positioning error M", fmt::format("{:.4f}", e.M), u);
  r.add_figure("targets x runs", fmt::format("{} x {}", e.targets.size(), e.runs), "per direction");
  if (e.runs < 5) r.add_warning(fmt::format("ISO 230-2 asks for 5 runs per direction; this has {}.", e.runs));

  r.add_section("Deviations");
  r.add_paragraph("Mean positional deviation per target and direction (x̄↑ up, x̄↓ down) with the ±2s bands that "
                  "define the accuracy A, and every run's deviation as a point.");
  json x = json::array(), up = x, dn = x, up_hi = x, up_lo = x, dn_hi = x, dn_lo = x, mean = x;
  json rx_up = x, ry_up = x, rx_dn = x, ry_dn = x;
  for (std::size_t i = 0; i < e.targets.size(); ++i) {
    const auto& t = e.targets[i];
    x.push_back(t.target);
    up.push_back(t.mean_up);
    dn.push_back(t.mean_down);
    mean.push_back(t.mean);
    up_hi.push_back(t.mean_up + 2 * t.s_up);
    up_lo.push_back(t.mean_up - 2 * t.s_up);
    dn_hi.push_back(t.mean_down + 2 * t.s_down);
    dn_lo.push_back(t.mean_down - 2 * t.s_down);
    for (double v : runs.up[i]) rx_up.push_back(t.target), ry_up.push_back(v - t.target);
    for (double v : runs.down[i]) rx_dn.push_back(t.target), ry_dn.push_back(v - t.target);
  }
  auto band = [&](const json& lo, const json& hi, const char* colour, const char* name) {
    return json::array({json{{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", lo}, {"line", {{"width", 0}}},
                             {"showlegend", false}, {"hoverinfo", "skip"}},
                        json{{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", hi}, {"fill", "tonexty"},
                             {"fillcolor", colour}, {"line", {{"width", 0}}}, {"name", name}}});
  };
  json data = json::array();
  for (auto& t : band(up_lo, up_hi, "rgba(31,119,180,0.2)", "x̄↑ ± 2s↑")) data.push_back(t);
  for (auto& t : band(dn_lo, dn_hi, "rgba(214,39,40,0.2)", "x̄↓ ± 2s↓")) data.push_back(t);
  data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"x", x}, {"y", up}, {"name", "x̄↑ (up)"},
                  {"line", {{"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"x", x}, {"y", dn}, {"name", "x̄↓ (down)"},
                  {"line", {{"color", "rgb(214,39,40)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", mean}, {"name", "x̄ (bidirectional)"},
                  {"line", {{"color", "black"}, {"dash", "dot"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "markers"}, {"x", rx_up}, {"y", ry_up}, {"name", "runs up"},
                  {"marker", {{"size", 4}, {"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "markers"}, {"x", rx_dn}, {"y", ry_dn}, {"name", "runs down"},
                  {"marker", {{"size", 4}, {"color", "rgb(214,39,40)"}}}});
  r.add_plot("Positional deviation x = measured − target (" + u + ") against the target position (" + u + ")",
             {{"data", data},
              {"layout", {{"xaxis", {{"title", {{"text", "target (" + u + ")"}}}}},
                          {"yaxis", {{"title", {{"text", "deviation (" + u + ")"}}}}}}}});

  r.add_section("Per target");
  std::vector<std::vector<std::string>> rows;
  for (const auto& t : e.targets)
    rows.push_back({fmt::format("{:g}", t.target), fmt::format("{:.5f}", t.mean_up), fmt::format("{:.5f}", t.mean_down),
                    fmt::format("{:.5f}", t.mean), fmt::format("{:.5f}", t.reversal), fmt::format("{:.5f}", t.s_up),
                    fmt::format("{:.5f}", t.s_down), fmt::format("{:.5f}", t.R_up), fmt::format("{:.5f}", t.R_down),
                    fmt::format("{:.5f}", t.R)});
  r.add_table("ISO 230-2 quantities per target (" + u + ")",
              {"target", "x̄↑", "x̄↓", "x̄", "B_i", "s↑", "s↓", "R↑", "R↓", "R_i"}, rows);
  r.add_table("Axis (" + u + ")", {"A", "A↑", "A↓", "B", "B̄", "R", "R↑", "R↓", "E", "E↑", "E↓", "M"},
              {{fmt::format("{:.5f}", e.A), fmt::format("{:.5f}", e.A_up), fmt::format("{:.5f}", e.A_down),
                fmt::format("{:.5f}", e.B), fmt::format("{:.5f}", e.B_mean), fmt::format("{:.5f}", e.R),
                fmt::format("{:.5f}", e.R_up), fmt::format("{:.5f}", e.R_down), fmt::format("{:.5f}", e.E),
                fmt::format("{:.5f}", e.E_up), fmt::format("{:.5f}", e.E_down), fmt::format("{:.5f}", e.M)}});
  r.write(o.report);
}

int run_iso230_2(const Iso2302Options& o) {
  check_outputs({o.file}, {o.report});
  const bool dat = o.format == "dat" || (o.format == "auto" && looks_like_dat(o.file));
  const PositioningRuns runs = dat ? read_positioning_dat(o.file) : read_positioning_csv(o.file, o.unit);
  const PositioningEvaluation e = evaluate_positioning(runs, o.file);
  if (!o.report.empty()) write_report(o, runs, e);
  if (o.json_out) {
    json j;
    for (const auto& [k, v] : std::initializer_list<std::pair<const char*, double>>{
             {"A", e.A}, {"A_up", e.A_up}, {"A_down", e.A_down}, {"B", e.B}, {"B_mean", e.B_mean}, {"R", e.R},
             {"R_up", e.R_up}, {"R_down", e.R_down}, {"E", e.E}, {"E_up", e.E_up}, {"E_down", e.E_down}, {"M", e.M}})
      j[k] = v;
    j["unit"] = e.unit;
    j["runs"] = e.runs;
    json ts = json::array();
    for (const auto& t : e.targets)
      ts.push_back({{"target", t.target}, {"mean_up", t.mean_up}, {"mean_down", t.mean_down}, {"mean", t.mean},
                    {"B", t.reversal}, {"s_up", t.s_up}, {"s_down", t.s_down}, {"R_up", t.R_up},
                    {"R_down", t.R_down}, {"R", t.R}});
    j["targets"] = ts;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("ISO 230-2: {} targets x {} runs per direction, unit {}\n", e.targets.size(), e.runs, e.unit);
  std::cout << fmt::format("{:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "target", "mean_up",
                           "mean_down", "B_i", "s_up", "s_down", "R_i", "mean");
  for (const auto& t : e.targets)
    std::cout << fmt::format("{:>10g} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f}\n", t.target,
                             t.mean_up, t.mean_down, t.reversal, t.s_up, t.s_down, t.R, t.mean);
  std::cout << fmt::format("A {:.5f} (up {:.5f}, down {:.5f})   R {:.5f} (up {:.5f}, down {:.5f})\n", e.A, e.A_up,
                           e.A_down, e.R, e.R_up, e.R_down);
  std::cout << fmt::format("B {:.5f} (mean {:.5f})   E {:.5f} (up {:.5f}, down {:.5f})   M {:.5f}   [{}]\n", e.B,
                           e.B_mean, e.E, e.E_up, e.E_down, e.M, e.unit);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

struct BallbarCliOptions {
  std::string trace, plane = "XY", direction, report, out, centre;
  ModelOptions model;
  double radius = 150, feed = 0, overshoot_start = 0, overshoot_stop = 0, step_deg = 1;
  bool predict = false, json_out = false;
};

json deviation_json(const CircularDeviation& d) {
  return {{"points", d.points}, {"G", d.G}, {"G_minimum_zone", d.G_minimum_zone},
          {"centre", {d.centre_x, d.centre_y}}, {"minimum_zone_centre", {d.mz_centre_x, d.mz_centre_y}},
          {"F_max", d.F_max}, {"F_min", d.F_min}, {"F_mean", d.F_mean}};
}

void write_ballbar_report(const BallbarCliOptions& o, const std::vector<TracePoint>& t, const BallbarEvaluation& e,
                          const TraceDiagnosis* diagnosis) {
  Report r("ISO 230-4 circular test, plane " + o.plane, command_line());
  r.add_input("trace", o.trace);
  r.add_figure("nominal radius", fmt::format("{:g}", o.radius), "mm");
  if (o.feed > 0) r.add_figure("feed", fmt::format("{:g}", o.feed), "mm/min");
  if (e.cw) r.add_figure("G (CW)", fmt::format("{:.2f}", e.cw->G * 1e3), "µm");
  if (e.ccw) r.add_figure("G (CCW)", fmt::format("{:.2f}", e.ccw->G * 1e3), "µm");
  if (e.G_b) r.add_figure("G(b)", fmt::format("{:.2f}", *e.G_b * 1e3), "µm");
  if (e.H) r.add_figure("H", fmt::format("{:.2f}", *e.H * 1e3), "µm");
  r.add_figure("F max / min", fmt::format("{:.2f} / {:.2f}", e.F_max * 1e3, e.F_min * 1e3), "µm");
  r.add_section("Trace");
  r.add_paragraph("Radial deviation of the bar from the nominal radius (µm), magnified round the circle, for both "
                  "directions, as ballbar software shows it.");
  json data = json::array();
  for (CircleDirection d : {CircleDirection::CW, CircleDirection::CCW}) {
    json th = json::array(), rr = json::array();
    for (const auto& s : t)
      if (s.direction == d) {
        th.push_back(s.angle * 180 / std::numbers::pi);
        rr.push_back((s.radius - o.radius) * 1e3);
      }
    data.push_back({{"type", "scatterpolar"}, {"mode", "lines"}, {"theta", th}, {"r", rr},
                    {"name", d == CircleDirection::CW ? "CW" : "CCW"}});
  }
  const double lo = std::floor(e.F_min * 1e3) - 1, hi = std::ceil(e.F_max * 1e3) + 1;
  json radial = {{"range", {lo, hi}}, {"title", {{"text", "µm"}}}};
  json layout = {{"polar", {{"radialaxis", radial}}}};
  r.add_plot("Radial deviation (µm) against the angle in the test plane", {{"data", data}, {"layout", layout}});
  std::vector<std::vector<std::string>> rows;
  for (const auto& [name, d] : {std::pair{"CW", e.cw}, std::pair{"CCW", e.ccw}})
    if (d)
      rows.push_back({name, fmt::format("{}", d->points), fmt::format("{:.3f}", d->G * 1e3),
                      fmt::format("{:.3f}", d->G_minimum_zone * 1e3), fmt::format("{:.3f}", d->F_max * 1e3),
                      fmt::format("{:.3f}", d->F_min * 1e3), fmt::format("{:.3f}, {:.3f}", d->centre_x * 1e3, d->centre_y * 1e3)});
  r.add_table("ISO 230-4 per direction (µm)", {"direction", "samples", "G", "G minimum zone", "F max", "F min",
                                              "least-squares centre (µm)"},
              rows);
  if (diagnosis) {
    r.add_section("Diagnostics");
    r.add_paragraph(fmt::format("Least-squares fit of a physical model of the trace (docs/evaluations.md); the share is "
                                "each term's RMS over the RMS of the fitted trace. What the model leaves: {:.3f} µm rms.",
                                diagnosis->residual_rms));
    json names = json::array(), shares = json::array();
    std::vector<std::vector<std::string>> drows;
    for (const auto& term : diagnosis->terms) {
      names.push_back(term.name);
      shares.push_back(term.share);
      std::string unit = term.unit == "um" ? "µm" : "µm/m";
      drows.push_back({term.name, fmt::format("{:.3f}", term.value), fmt::format("{:.3f}", term.uncertainty), unit,
                       fmt::format("{:.1f}", term.share)});
    }
    r.add_plot("Share of each diagnostic term in the fitted trace (%)",
               {{"data", {{{"type", "bar"}, {"x", names}, {"y", shares}, {"name", "share"}}}},
                {"layout", {{"yaxis", {{"title", {{"text", "%"}}}}}}}});
    r.add_table("Diagnostic terms", {"term", "value", "standard uncertainty", "unit", "share (%)"}, drows);
  }
  r.write(o.report);
}

int run_ballbar(const BallbarCliOptions& o) {
  if (o.predict) {
    if (o.model.machine.empty() || o.out.empty())
      throw InputError({"--predict", 0, ""}, "--predict needs --machine and --out");
    check_outputs(model_inputs(o.model), {o.out});
    const Machine m = load(o.model);
    const auto centre = parse_joint_values(m, o.centre, "--centre");
    const auto t = predict_ballbar(m, o.plane, centre, o.radius, o.step_deg * std::numbers::pi / 180);
    AtomicFile f(o.out);
    f.stream() << "direction,angle_deg,radius_mm\n";
    for (const auto& s : t)
      f.stream() << fmt::format("{},{:.6f},{:.9f}\n", s.direction == CircleDirection::CW ? "cw" : "ccw",
                                s.angle * 180 / std::numbers::pi, s.radius);
    f.commit();
    std::cout << fmt::format("predicted {} samples of a {} mm circle in {} on {}: wrote {}\n", t.size(), o.radius,
                             o.plane, m.name, o.out);
    return 0;
  }
  if (o.trace.empty()) throw InputError({"ballbar", 0, ""}, "expected a trace file (or --predict)");
  check_outputs({o.trace}, {o.report});
  BallbarOptions bo;
  bo.nominal_radius = o.radius;
  bo.overshoot_start = o.overshoot_start;
  bo.overshoot_stop = o.overshoot_stop;
  if (o.direction == "cw") bo.only = CircleDirection::CW;
  if (o.direction == "ccw") bo.only = CircleDirection::CCW;
  const auto t = read_ballbar_csv(o.trace);
  const auto e = evaluate_ballbar(t, bo, o.trace);
  std::optional<TraceDiagnosis> diagnosis;
  if (!bo.only) diagnosis = diagnose_ballbar(t, bo, o.plane, o.trace);
  if (!o.report.empty()) write_ballbar_report(o, t, e, diagnosis ? &*diagnosis : nullptr);
  if (o.json_out) {
    json j;
    j["plane"] = o.plane;
    j["radius"] = o.radius;
    if (o.feed > 0) j["feed"] = o.feed;
    j["G_cw"] = e.cw ? json(e.cw->G) : json(nullptr);
    j["G_ccw"] = e.ccw ? json(e.ccw->G) : json(nullptr);
    j["G_b"] = e.G_b ? json(*e.G_b) : json(nullptr);
    j["H"] = e.H ? json(*e.H) : json(nullptr);
    j["F_max"] = e.F_max;
    j["F_min"] = e.F_min;
    j["F_mean_bidirectional"] = e.F_mean_bidirectional ? json(*e.F_mean_bidirectional) : json(nullptr);
    if (e.cw) j["cw"] = deviation_json(*e.cw);
    if (e.ccw) j["ccw"] = deviation_json(*e.ccw);
    if (diagnosis) {
      json dj = json::object();
      for (const auto& term : diagnosis->terms)
        dj[term.name] = {{"value", term.value}, {"u", term.uncertainty}, {"unit", term.unit}, {"share", term.share}};
      j["diagnostics"] = dj;
      j["diagnostics_residual_rms_um"] = diagnosis->residual_rms;
    }
    j["units"] = "mm";
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("ISO 230-4 circular test, plane {}, radius {:g} mm{}\n", o.plane, o.radius,
                           o.feed > 0 ? fmt::format(", feed {:g} mm/min", o.feed) : std::string());
  for (const auto& [name, d] : {std::pair{"CW ", e.cw}, std::pair{"CCW", e.ccw}})
    if (d)
      std::cout << fmt::format("{}  G {:.2f} um (minimum zone {:.2f})  F max {:.2f} min {:.2f} um  ({} samples)\n", name,
                               d->G * 1e3, d->G_minimum_zone * 1e3, d->F_max * 1e3, d->F_min * 1e3, d->points);
  if (e.G_b) std::cout << fmt::format("G(b) {:.2f} um   H {:.2f} um   mean radial deviation {:.2f} um\n", *e.G_b * 1e3,
                                      *e.H * 1e3, *e.F_mean_bidirectional * 1e3);
  if (diagnosis) {
    std::cout << "diagnostics (least-squares fit of the trace model; share of the fitted trace):\n";
    for (const auto& term : diagnosis->terms)
      std::cout << fmt::format("  {:<34} {:>9.3f} +- {:<7.3f} {:<5} {:>5.1f} %\n", term.name, term.value,
                               term.uncertainty, term.unit, term.share);
    std::cout << fmt::format("  residual rms {:.3f} um\n", diagnosis->residual_rms);
  }
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_evaluation_commands(CLI::App& app) {
  auto o = std::make_shared<Iso2302Options>();
  auto* c = app.add_subcommand("iso230-2", "ISO 230-2 linear positioning: accuracy A, repeatability R, reversal B, "
                                           "systematic and mean positioning errors E and M, per target and per axis");
  c->add_option("file", o->file, "Measurements: CSV target,run,direction,measured (direction up/down or +/-), or "
                                 "the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT)")
      ->required();
  c->add_option("--unit", o->unit, "Unit of a CSV's values (a .dat file says its own)")->capture_default_str();
  c->add_option("--format", o->format, "Input format: auto (by .dat extension or content), csv or dat")
      ->check(CLI::IsMember({"auto", "csv", "dat"}))
      ->capture_default_str();
  c->add_flag("--json", o->json_out, "Machine-readable output: A A_up A_down B B_mean R R_up R_down E E_up E_down M at "
                                     "the top level (input unit), per-target values under targets");
  c->add_option("--report", o->report, "Write an HTML report: deviations with ±2s bands per direction, tables");
  auto b = std::make_shared<BallbarCliOptions>();
  auto* bb = app.add_subcommand("ballbar", "ISO 230-4 circular test: G per direction (least-squares and minimum-zone "
                                           "centres), G(b), H, F from a ballbar trace; or --predict the trace of a "
                                           "machine model");
  bb->add_option("trace", b->trace, "Trace CSV direction,angle_deg,radius_mm (direction cw or ccw)");
  bb->add_option("--radius", b->radius, "Nominal radius, mm")->check(CLI::PositiveNumber & kFinite)->capture_default_str();
  bb->add_option("--plane", b->plane, "Test plane: XY, YZ or ZX")->check(CLI::IsMember({"XY", "YZ", "ZX"}))->capture_default_str();
  bb->add_option("--feed", b->feed, "Feed, mm/min (recorded in the output)")->check(kFinite);
  bb->add_option("--overshoot-start", b->overshoot_start, "Degrees of travel ignored after each direction's start")
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--overshoot-stop", b->overshoot_stop, "Degrees of travel ignored before each direction's end")
      ->check(CLI::Range(0.0, 180.0) & kFinite);
  bb->add_option("--direction", b->direction, "Evaluate one direction only: cw or ccw (no G(b), no H)")
      ->check(CLI::IsMember({"cw", "ccw"}));
  bb->add_flag("--json", b->json_out, "Machine-readable output: G_cw G_ccw G_b H F_max F_min F_mean_bidirectional "
                                      "(mm), per direction under cw and ccw");
  bb->add_option("--report", b->report, "Write an HTML report with the polar plot of both directions");
  bb->add_flag("--predict", b->predict, "Predict the trace of --machine instead of evaluating one");
  bb->add_option("--machine,-m", b->model.machine, "Machine file, with --predict");
  bb->add_option("--params", b->model.params, "Parameter files applied to the machine, with --predict");
  bb->add_option("--centre", b->centre, "Centre of the circle as joint values, e.g. \"X=0,Y=0,Z=-100\" (mm, deg)");
  bb->add_option("--step-deg", b->step_deg, "Angle between predicted samples, deg")->check(CLI::Range(0.01, 10.0) & kFinite);
  bb->add_option("--out", b->out, "Trace CSV to write, with --predict");
  return {{c, [o] { return run_iso230_2(*o); }}, {bb, [b] { return run_ballbar(*b); }}};
}

}  // namespace mtcal::cli
