// mtcal regress, predict, separate: workpiece error prediction after Yaqoob 2017 (ch. 3, 5, 6).
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/json/prediction_json.hpp"
#include "mtcal/io/model/prediction_model_file.hpp"
#include "mtcal/io/points/prediction_points.hpp"
#include "mtcal/io/instruments/separation_file.hpp"
#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/process_error.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/prediction/separation.hpp"
#include "mtcal/report/prediction.hpp"
#include "mtcal/report/recorded.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

std::string g6(double v) { return significant6(v); }

// ---------------------------------------------------------------- regress
struct RegressOptions {
  std::string data, x, y, models = "all", report;
  bool json_out = false;
};

void print_regression(const RegressOptions& o, const ModelComparison& c, std::size_t n) {
  std::cout << fmt::format("{} points, {} = f({}), {} models fitted\n", n, o.y, o.x, c.fits.size());
  std::cout << fmt::format("{:<22} {:>12} {:>12} {:>12} {:>12}  {}\n", "model", "backward", "backward max", "LOO RMSE",
                           "R^2", "parameters");
  for (std::size_t i : c.by_backward) {
    const auto& f = c.fits[i];
    std::cout << fmt::format("{:<22} {:>12} {:>12} {:>12} {:>12}  {}\n", f.model.spec.label(), g6(f.backward.mean),
                             g6(f.backward.max), f.loocv_rmse ? g6(*f.loocv_rmse) : "-", g6(f.r_squared),
                             fit_parameters_text(f));
  }
  for (const auto& s : c.skipped) std::cout << fmt::format("not fitted: {}: {}\n", s.spec.label(), s.reason);
  std::cout << fmt::format("best by backward prediction (sec. 3.8): {}\nbest by leave-one-out:              {}\n",
                           c.fits[c.by_backward[0]].model.spec.label(), c.fits[c.by_loocv[0]].model.spec.label());
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_regress(const RegressOptions& o) {
  check_outputs({o.data}, {o.report});
  if (!o.report.empty()) AtomicFile check(o.report);
  const auto specs = parse_model_specs(o.models, "--models");
  const TableRegression g = regress_table(read_csv(o.data), o.data, o.x, o.y, specs);
  const ModelComparison& c = g.comparison;
  const std::vector<double>&x = g.x, &y = g.y;
  if (!o.report.empty()) regression_report(c, x, y, o.data, o.x, o.y, command_line()).write(o.report);
  if (recording())
    note_report_source(o.data, regression_invocation(command_line(), o.data, o.x, o.y, o.models, session_metadata()));
  if ((o.json_out || recording()) && emit_json(to_json(c, o.data, o.x, o.y, x.size(), o.report), o.json_out)) {
    return 0;
  }
  print_regression(o, c, x.size());
  return 0;
}

// ---------------------------------------------------------------- predict
struct PredictOptions {
  std::string model, points, gcode, out, compensation, report, set;
  double start_time = 0, speed = 0, rapid_feed = 10000;
  bool json_out = false, strict = false;
};

// --set "NAME=VALUE,...": constant variables.
std::map<std::string, double> constants_of(const std::string& set) {
  std::map<std::string, double> constants;
  for (const auto& item : split_list(set)) {
    const auto eq = item.find('=');
    const auto v = eq == std::string::npos ? std::nullopt : parse_number(item.substr(eq + 1));
    if (!v || eq == 0)
      throw InputError({"--set", 0, item},
                       "expected NAME=VALUE items separated by commas, found '" + printable(item) + "'");
    constants[item.substr(0, eq)] = *v;
  }
  return constants;
}

PredictionPoints points_of(const PredictOptions& o) {
  if (!o.points.empty()) return read_prediction_points(o.points);
  if (o.speed <= 0) throw InputError({"--speed", 0, ""}, "--gcode needs --speed (spindle speed, rpm > 0)");
  return points_from_gcode(read_gcode(o.gcode, GcodeOptions{"XYZ", {}, {}}), o.gcode, o.start_time, o.speed,
                           o.rapid_feed);
}

void print_prediction(const PredictOptions& o, const PredictionRun& run, const PredictionModel& m) {
  std::cout << fmt::format("{} points, {} components ({})\n", run.predictions.size(), m.components.size(), m.name);
  std::cout << fmt::format("{:>6} {:>12} {:>12} {:>12}\n", "line", "ex (mm)", "ey (mm)", "ez (mm)");
  for (std::size_t r = 0; r < run.predictions.size(); ++r) {
    const auto& e = run.predictions[r].e;
    std::cout << fmt::format("{:>6} {:>12.6f} {:>12.6f} {:>12.6f}\n", run.points.lines[r], e[0], e[1], e[2]);
  }
  for (const auto& w : run.warnings) std::cout << "warning: " << w << "\n";
  if (!o.out.empty()) std::cout << "points with every component written to " << o.out << "\n";
  if (!o.compensation.empty()) std::cout << "compensation offsets per step written to " << o.compensation << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_predict(const PredictOptions& o) {
  if (o.points.empty() == o.gcode.empty())
    throw InputError({"predict", 0, ""}, "expected exactly one of --points, --gcode");
  check_outputs({o.model, o.points, o.gcode}, {o.out, o.compensation, o.report});
  for (const auto* p : {&o.out, &o.compensation, &o.report})
    if (!p->empty()) AtomicFile check(*p);
  const PredictionModel m = read_prediction_model(o.model);
  const PredictionPoints t = points_of(o);
  const std::map<std::string, double> constants = constants_of(o.set);
  for (const auto& v : missing_variables(m, t, constants)) {
    std::string users;
    for (const auto& u : components_reading(m, v)) users += (users.empty() ? "" : ", ") + u;
    throw InputError({t.source, 0, v},
                     fmt::format("missing column '{}' needed by {} (give it as a column or with --set {}=VALUE)", v,
                                 users, v));
  }
  if (!o.compensation.empty() && t.column("step") < 0)
    throw InputError({t.source, 0, "step"}, "--compensation needs a 'step' column in the points");
  const PredictionRun run = predict_points(m, t, constants, o.strict, !o.compensation.empty());
  if (!o.compensation.empty()) write_file_atomically(o.compensation, compensation_csv(run));
  if (!o.out.empty()) write_file_atomically(o.out, prediction_csv(run, m));
  if (!o.report.empty())
    prediction_report(run, m, o.model, o.gcode.empty() ? "points" : "G-code", command_line()).write(o.report);
  if (o.json_out) {
    print_json(to_json(run, m));
    return 0;
  }
  print_prediction(o, run, m);
  return 0;
}

// ---------------------------------------------------------------- separate
struct SeparateOptions {
  std::string kind, data, a, b, model, out;
  bool json_out = false;
};

int print_separation(const SeparateOptions& o, const std::string& csv, const Json& j) {
  if (o.json_out) {
    print_json(j);
    return 0;
  }
  std::cout << csv;
  if (j.contains("warnings"))
    for (const auto& w : j["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
  if (j.contains("fits"))
    for (const auto& [name, f] : j["fits"].items()) {
      std::string p;
      for (const auto& [k, v] : f["parameters"].items())
        p += fmt::format(" {}={}", k, v["value"].is_null() ? std::string("-") : g6(v["value"].get<double>()));
      std::cout << fmt::format("{} = {}:{}\n", name, f["model"].get<std::string>(), p);
    }
  if (!o.out.empty()) std::cout << "written to " << o.out << "\n";
  return 0;
}

int run_separate(const SeparateOptions& o) {
  check_outputs({o.data, o.model}, {o.out});
  if (!o.out.empty()) AtomicFile check(o.out);
  const TextTable t = read_text_csv(o.data);
  std::string csv;
  Json j;
  if (o.kind == "position") {
    const PositionSeparation s = separate_position_with_fits(read_position_observations(t, o.data));
    csv = separation_csv(s);
    j = to_json(s, o.data);
  } else {
    if (o.a.empty() || o.b.empty())
      throw InputError({"--a", 0, ""}, "separate control needs --a and --b (workpiece names)");
    const auto rec = read_dimension_table(t, o.data);
    std::optional<PredictionModel> m;
    if (!o.model.empty()) m = read_prediction_model(o.model);
    const ControlSeparation s = separate_control(rec, o.a, o.b, o.data, m ? &*m : nullptr);
    csv = separation_csv(s);
    j = to_json(s, o.data);
  }
  if (!o.out.empty()) write_file_atomically(o.out, csv);
  return print_separation(o, csv, j);
}

// ---------------------------------------------------------------- process-error
struct ProcessErrorOptions {
  std::string feeds, measured, form = "logistic_ln";
  EndMill tool;
  CuttingCoefficients k;
  CutConditions cut;
  bool up_milling = false, json_out = false;
};

std::vector<double> number_list(const std::string& text, const char* option) {
  std::vector<double> v;
  for (const auto& item : split_list(text)) {
    const auto x = parse_number(item);
    if (!x) throw InputError({option, 0, item}, fmt::format("expected a comma list of numbers, found '{}'", item));
    v.push_back(*x);
  }
  if (v.empty()) throw InputError({option, 0, ""}, "expected a comma list of numbers, found nothing");
  return v;
}

void print_process_error(const ProcessErrorStudy& s) {
  const EndMill& t = s.tool;
  std::cout << fmt::format(
      "tool D {:g} mm, {} teeth, helix {:g} deg, overhang {:g} mm, flutes {:g} mm at {:g} D, E {:g} N/mm^2\n",
      t.diameter, t.teeth, t.helix_deg, t.overhang, t.flute_length, t.flute_diameter_ratio, t.young_modulus);
  std::cout << fmt::format(
      "cut ae {:g} mm, ap {:g} mm, {:g} rpm, {} milling; Ktc {:g} Krc {:g} N/mm^2, Kte {:g} Kre {:g} N/mm\n",
      s.cut.radial_depth, s.cut.axial_depth, s.cut.spindle_speed, s.cut.down_milling ? "down" : "up", s.k.ktc, s.k.krc,
      s.k.kte, s.k.kre);
  std::cout << fmt::format("{:>10} {:>12} {:>12} {:>12} {:>12} {:>14}\n", "F (mm/min)", "fz (mm)", "mean Fx (N)",
                           "mean Fy (N)", "peak |Fy| (N)", "e_prog (mm)");
  for (const auto& r : s.points)
    std::cout << fmt::format("{:>10g} {:>12.6g} {:>12.6g} {:>12.6g} {:>12.6g} {:>14.6g}\n", r.feed, r.fz,
                             r.forces.mean_x, r.forces.mean_y, r.forces.peak_y, r.e_prog);
  if (s.calibration) {
    const auto& f = s.calibration->fit;
    std::cout << fmt::format("calibration measured = {}(e_prog) (eq. 5.49-5.51): {}\n", f.model.spec.label(),
                             fit_parameters_text(f));
    std::cout << fmt::format("  RSS {}  R^2 {}  backward mean |diff| {}  max {}\n", g6(f.rss), g6(f.r_squared),
                             g6(f.backward.mean), g6(f.backward.max));
  }
}

// e_prog (Yaqoob 2017 sec. 3.7, 5.5.1) per feed, and with --measured the calibration of the
// measured process errors on it (eq. 5.49-5.51).
int run_process_error(ProcessErrorOptions o) {
  o.cut.down_milling = !o.up_milling;
  const std::vector<double> feeds = number_list(o.feeds, "--feed");
  std::vector<double> measured;
  std::optional<ModelSpec> spec;
  if (!o.measured.empty()) {
    measured = number_list(o.measured, "--measured");
    if (measured.size() != feeds.size())
      throw InputError({"--measured", 0, ""}, fmt::format("expected one measured process error per feed ({}), found {}",
                                                          feeds.size(), measured.size()));
    const auto specs = parse_model_specs(o.form, "--form");
    if (specs.size() != 1)
      throw InputError({"--form", 0, o.form}, "expected one model form for the calibration, found " + o.form);
    spec = specs[0];
  }
  const ProcessErrorStudy s = process_error_study(o.tool, o.k, o.cut, feeds, measured, spec);
  if (o.json_out)
    print_json(to_json(s));
  else
    print_process_error(s);
  return 0;
}

Command add_regress(CLI::App& app) {
  auto ro = std::make_shared<RegressOptions>();
  auto* r = app.add_subcommand(
      "regress",
      "Fit the regression forms of Yaqoob 2017 (polynomial, exp_approach, stretched_exp, logistic_ln, "
      "gompertz, saturation, power) to y(x) with uncertainties; rank by backward-prediction error "
      "(sec. 3.8) and by leave-one-out cross-validation");
  r->add_option("DATA", ro->data, "CSV with a header; the columns --x and --y are used")->required();
  r->add_option("--x", ro->x, "Column of the driving variable (e.g. t)")->required();
  r->add_option("--y", ro->y, "Column of the error (e.g. e)")->required();
  r->add_option("--models", ro->models, "all, or a comma list: polynomial(1..3), polynomial(2,c0=0), exp_approach, ...")
      ->capture_default_str();
  r->add_flag(
      "--json", ro->json_out,
      "Machine-readable output: file x y n fits[] (model form parameters{value,stddev} rss sigma dof "
      "r_squared aicc backward{mean,max,mean_relative,abs_diff} loocv_rmse) skipped[] best_backward best_loocv");
  r->add_option("--report", ro->report, "Write an HTML report: data with every fitted curve, table of criteria");
  return {r, [ro] { return run_regress(*ro); }};
}

Command add_predict(CLI::App& app) {
  auto po = std::make_shared<PredictOptions>();
  auto* p =
      app.add_subcommand("predict",
                         "Predict the X, Y, Z errors of a workpiece from a prediction model (Yaqoob 2017 ch. 6): every "
                         "component per point and their sums; compensation offsets per step");
  p->add_option("--model", po->model, "Prediction model YAML (docs/prediction.md)")->required();
  p->add_option("--points", po->points,
                "CSV of points: a column per variable the model reads (t, S, F, dx, dy, dz ...), optional step");
  p->add_option("--gcode", po->gcode, "Or a G-code program: a point per move end (needs --speed; --start-time)");
  p->add_option("--start-time", po->start_time, "Minutes since machine start at the program's first block (--gcode)")
      ->check(kFinite);
  p->add_option("--speed", po->speed, "Spindle speed for --gcode (rpm)")->check(kFinite);
  p->add_option("--rapid-feed", po->rapid_feed, "Feed of G0 moves for the time stamps (mm/min)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  p->add_option("--set", po->set, "Constant variables not in the points, e.g. \"h_tt=10,h_spd=9\"");
  p->add_flag("--strict", po->strict,
              "Refuse a point outside a component's validity range (default: extrapolate with a warning)");
  p->add_option("--out", po->out, "Write the points with every component and ex, ey, ez to this CSV");
  p->add_option("--compensation", po->compensation,
                "Write offsets per step (step,offset_x,offset_y,offset_z = -mean predicted error)");
  p->add_flag("--json", po->json_out,
              "Machine-readable output: model source components[] (name axis source) points[] (line input "
              "components ex ey ez) warnings[] compensation[]");
  p->add_option("--report", po->report, "Write an HTML report: components per point and axis, table");
  return {p, [po] { return run_predict(*po); }};
}

Command add_separate(CLI::App& app) {
  auto so = std::make_shared<SeparateOptions>();
  auto* s = app.add_subcommand(
      "separate",
      "Separate error components from measured workpieces (Yaqoob 2017 sec. 3.3-3.6): position errors "
      "(CMM - probe per step, with eq. 5.1-5.3 fits) or control errors between two workpieces (eq. 3.11-3.15)");
  s->add_option("KIND", so->kind, "position or control")->required()->check(CLI::IsMember({"position", "control"}));
  s->add_option(
       "DATA", so->data,
       "position: step,d_x,d_y,d_z,cmm_<F>,probe_<F>...; control: workpiece,step,axis,nominal,measured,e_pf,e_pt,e_pos")
      ->required();
  s->add_option("--a", so->a, "control: first workpiece (e.g. W2)");
  s->add_option("--b", so->b,
                "control: second workpiece (W8 for e_ctrl, eq. 3.11-3.12; W5 with --model for e_cpr, eq. 3.15)");
  s->add_option("--model", so->model,
                "control: prediction model whose e_ctrl_x / e_ctrl_y (eq. 5.52-5.53) are subtracted (eq. 3.15)");
  s->add_option("--out", so->out, "Write the separated values as CSV");
  s->add_flag("--json", so->json_out,
              "Machine-readable output: file kind steps[] (axis step distance e_pos count | e_ctrl/e_cpr) fits{}");
  return {s, [so] { return run_separate(*so); }};
}

Command add_process_error(CLI::App& app) {
  auto eo = std::make_shared<ProcessErrorOptions>();
  auto* e = app.add_subcommand(
      "process-error",
      "Program-generated process error e_prog (Yaqoob 2017 sec. 3.7): mechanistic milling forces and the "
      "tool as a two-section cantilever, per feed; with --measured, the calibration measured = f(e_prog) "
      "(eq. 5.49-5.51)");
  e->add_option("--feed", eo->feeds, "Feed(s) F (mm/min), a comma list, e.g. \"100,200,400,800,1600\"")->required();
  e->add_option("--speed", eo->cut.spindle_speed, "Spindle speed S (rpm)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  e->add_option("--ae", eo->cut.radial_depth, "Radial depth of cut (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--ap", eo->cut.axial_depth, "Axial depth of cut (mm)")->check(kFinite)->capture_default_str();
  e->add_flag("--up-milling", eo->up_milling, "Up (conventional) milling (default: down / climb milling)");
  e->add_option("--diameter", eo->tool.diameter, "Tool diameter D (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--teeth", eo->tool.teeth, "Number of teeth")->capture_default_str();
  e->add_option("--helix", eo->tool.helix_deg, "Helix angle (deg; 0: straight flutes)")
      ->check(kFinite)
      ->capture_default_str();
  e->add_option("--overhang", eo->tool.overhang, "Length out of the holder L (mm)")
      ->check(kFinite)
      ->capture_default_str();
  e->add_option("--flute-length", eo->tool.flute_length, "Fluted length from the tip (mm)")
      ->check(kFinite)
      ->capture_default_str();
  e->add_option("--flute-ratio", eo->tool.flute_diameter_ratio, "Equivalent diameter of the fluted section / D")
      ->check(kFinite)
      ->capture_default_str();
  e->add_option("--young", eo->tool.young_modulus, "Young's modulus E (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--ktc", eo->k.ktc, "Tangential cutting coefficient (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--krc", eo->k.krc, "Radial cutting coefficient (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--kte", eo->k.kte, "Tangential edge coefficient (N/mm)")->check(kFinite)->capture_default_str();
  e->add_option("--kre", eo->k.kre, "Radial edge coefficient (N/mm)")->check(kFinite)->capture_default_str();
  auto* measured = e->add_option("--measured", eo->measured,
                                 "Measured process errors (mm), one per feed: calibrate measured = f(e_prog)");
  // Refused without --measured (it would be ignored silently).
  e->add_option("--form", eo->form,
                "Calibration form: logistic_ln (eq. 5.49-5.50), saturation (eq. 5.51) or any regress form")
      ->capture_default_str()
      ->needs(measured);
  e->add_flag("--json", eo->json_out,
              "Machine-readable output: tool coefficients cut points[] (feed fz mean_fx mean_fy peak_fy e_prog) "
              "calibration (a regress fit with measured[])");
  return {e, [eo] { return run_process_error(*eo); }};
}

}  // namespace

std::vector<Command> add_prediction_commands(CLI::App& app) {
  return {add_regress(app), add_predict(app), add_separate(app), add_process_error(app)};
}

}  // namespace mtcal::cli
