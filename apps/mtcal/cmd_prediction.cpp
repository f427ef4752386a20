// mtcal regress, predict, separate: workpiece error prediction after Yaqoob 2017 (ch. 3, 5, 6).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/gcode.hpp"
#include "mtcal/prediction/prediction_model.hpp"
#include "mtcal/prediction/process_error.hpp"
#include "mtcal/prediction/regression.hpp"
#include "mtcal/prediction/separation.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;

json num_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
std::string g6(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string("-"); }

// ---------------------------------------------------------------- regress
struct RegressOptions {
  std::string data, x, y, models = "all", report;
  bool json_out = false;
};

json fit_json(const FitResult& f) {
  json p = json::object();
  const auto names = parameter_names(f.model.spec);
  for (std::size_t k = 0; k < names.size(); ++k)
    p[names[k]] = {{"value", num_or_null(f.model.p[k])},
                   {"stddev", num_or_null(f.stddev[k])},
                   {"at_bound", k < f.at_bound.size() && f.at_bound[k]},
                   {"identified", k < f.identified.size() && f.identified[k]}};
  return {{"model", f.model.spec.label()},
          {"form", std::string(to_string(f.model.spec.form))},
          {"parameters", p},
          {"identifiable", f.identifiable},
          {"rss", num_or_null(f.rss)},
          {"sigma", num_or_null(f.sigma)},
          {"dof", f.dof},
          {"r_squared", num_or_null(f.r_squared)},
          {"aicc", num_or_null(f.aicc)},
          {"backward", {{"mean", f.backward.mean}, {"max", f.backward.max}, {"mean_relative", num_or_null(f.backward.mean_relative)},
                        {"abs_diff", f.backward.abs_diff}}},
          {"loocv_rmse", f.loocv_rmse ? json(*f.loocv_rmse) : json(nullptr)}};
}

std::string params_text(const FitResult& f) {
  std::string s;
  const auto names = parameter_names(f.model.spec);
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::string note;
    if (k < f.at_bound.size() && f.at_bound[k]) note = " (at bound)";
    else if (k < f.identified.size() && !f.identified[k]) note = " (not identifiable)";
    else if (std::isfinite(f.stddev[k])) note = "±" + g6(f.stddev[k]);
    s += fmt::format("{}{}={}{}", s.empty() ? "" : " ", names[k], g6(f.model.p[k]), note);
  }
  return s;
}

int run_regress(const RegressOptions& o) {
  check_outputs({o.data}, {o.report});
  if (!o.report.empty()) AtomicFile check(o.report);
  const auto specs = parse_model_specs(o.models, "--models");
  const CsvTable t = read_csv(o.data);
  const int cx = t.column(o.x), cy = t.column(o.y);
  if (cx < 0) throw InputError({o.data, 0, o.x}, "no column '" + o.x + "' (--x)");
  if (cy < 0) throw InputError({o.data, 0, o.y}, "no column '" + o.y + "' (--y)");
  std::vector<double> x, y;
  for (const auto& r : t.rows) {
    x.push_back(r[static_cast<std::size_t>(cx)]);
    y.push_back(r[static_cast<std::size_t>(cy)]);
  }
  if (x.size() < 2) throw InputError({o.data, 0, o.y}, fmt::format("expected at least 2 rows, found {}", x.size()));
  const ModelComparison c = compare_models(specs, x, y);
  if (c.fits.empty()) throw Error("no model could be fitted: " + (c.skipped.empty() ? std::string() : c.skipped[0].reason));
  const FitResult& bb = c.fits[c.by_backward[0]];
  const FitResult& bl = c.fits[c.by_loocv[0]];

  if (!o.report.empty()) {
    Report r("Regression: " + o.y + " vs " + o.x, command_line());
    r.add_input("data", o.data);
    r.add_figure("points", fmt::format("{}", x.size()), "");
    r.add_figure("best by backward prediction (sec. 3.8)", bb.model.spec.label(), fmt::format("mean |diff| {}", g6(bb.backward.mean)));
    r.add_figure("best by leave-one-out", bl.model.spec.label(), bl.loocv_rmse ? "RMSE " + g6(*bl.loocv_rmse) : "");
    for (const auto& s : c.skipped) r.add_warning(s.spec.label() + " not fitted: " + s.reason);
    r.add_section("Data and fitted models");
    nlohmann::json data = nlohmann::json::array();
    data.push_back({{"type", "scatter"}, {"mode", "markers"}, {"name", "data"}, {"x", x}, {"y", y}});
    const double lo = *std::min_element(x.begin(), x.end()), hi = *std::max_element(x.begin(), x.end());
    for (const auto& f : c.fits) {
      std::vector<double> cxv;
      nlohmann::json cyv = nlohmann::json::array();  // null where the model is undefined: a gap, not 0
      for (int i = 0; i <= 200; ++i) {
        const double v = lo + (hi - lo) * i / 200.0;
        cxv.push_back(v);
        const double fv = f.model(v);
        cyv.push_back(std::isfinite(fv) ? nlohmann::json(fv) : nlohmann::json(nullptr));
      }
      data.push_back({{"type", "scatter"}, {"mode", "lines"}, {"name", f.model.spec.label()}, {"x", cxv}, {"y", cyv}});
    }
    r.add_plot("Data and every fitted model",
               {{"data", data}, {"layout", {{"xaxis", {{"title", {{"text", o.x}}}}}, {"yaxis", {{"title", {{"text", o.y}}}}}}}});
    r.add_section("Criteria");
    r.add_paragraph("Backward-prediction error (Yaqoob 2017 section 3.8, Table 5.8): |y - f(x)| at the measured points of "
                    "the model fitted to all of them; ranked by its mean. It is an in-sample criterion and favours models "
                    "with more parameters; the leave-one-out RMSE predicts each point from a refit without it.");
    std::vector<std::vector<std::string>> rows;
    for (const auto& f : c.fits)
      rows.push_back({f.model.spec.label(), params_text(f), g6(f.rss), g6(f.r_squared), g6(f.backward.mean), g6(f.backward.max),
                      f.loocv_rmse ? g6(*f.loocv_rmse) : "-", g6(f.aicc)});
    r.add_table("Fitted models (parameters ± standard uncertainty)",
                {"model", "parameters", "RSS", "R²", "mean backward |diff|", "max backward |diff|", "LOO RMSE", "AICc"}, rows);
    r.write(o.report);
  }

  if (o.json_out) {
    json j;
    j["file"] = o.data;
    j["x"] = o.x;
    j["y"] = o.y;
    j["n"] = x.size();
    j["fits"] = json::array();
    for (const auto& f : c.fits) j["fits"].push_back(fit_json(f));
    j["skipped"] = json::array();
    for (const auto& s : c.skipped) j["skipped"].push_back({{"model", s.spec.label()}, {"reason", s.reason}});
    j["best_backward"] = bb.model.spec.label();
    j["best_loocv"] = bl.model.spec.label();
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{} points, {} = f({}), {} models fitted\n", x.size(), o.y, o.x, c.fits.size());
  std::cout << fmt::format("{:<22} {:>12} {:>12} {:>12} {:>12}  {}\n", "model", "backward", "backward max", "LOO RMSE", "R^2", "parameters");
  for (std::size_t i : c.by_backward) {
    const auto& f = c.fits[i];
    std::cout << fmt::format("{:<22} {:>12} {:>12} {:>12} {:>12}  {}\n", f.model.spec.label(), g6(f.backward.mean), g6(f.backward.max),
                             f.loocv_rmse ? g6(*f.loocv_rmse) : "-", g6(f.r_squared), params_text(f));
  }
  for (const auto& s : c.skipped) std::cout << fmt::format("not fitted: {}: {}\n", s.spec.label(), s.reason);
  std::cout << fmt::format("best by backward prediction (sec. 3.8): {}\nbest by leave-one-out:              {}\n",
                           bb.model.spec.label(), bl.model.spec.label());
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

// ---------------------------------------------------------------- predict
struct PredictOptions {
  std::string model, points, gcode, out, compensation, report, set;
  double start_time = 0, speed = 0, rapid_feed = 10000;
  bool json_out = false, strict = false;
};

struct PointTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;
  std::string source;
};

// --gcode: one point per cutting move's end (G1, G2, G3); t = start + time so far (length /
// feed), F = the move's feed, S = --speed, dx dy dz = |X| |Y| |Z| (distance from the program
// zero, as Table 6.7 evaluates e_pos at the coordinates). A rapid (G0) cuts nothing: it only
// advances the time, at --rapid-feed, and gives no point (the process and control models are of
// cutting feeds, 100-1600 mm/min).
PointTable points_from_gcode(const PredictOptions& o) {
  if (o.speed <= 0) throw InputError({"--speed", 0, ""}, "--gcode needs --speed (spindle speed, rpm > 0)");
  const GcodeProgram prog = read_gcode(o.gcode, GcodeOptions{"XYZ", {}});
  PointTable t;
  t.source = o.gcode;
  t.columns = {"line", "X", "Y", "Z", "t", "S", "F", "dx", "dy", "dz"};
  double minutes = o.start_time;
  for (const auto& m : prog.moves) {
    if (m.motion == GcodeMotion::Rapid) {
      minutes += path_length(m) / o.rapid_feed;
      continue;
    }
    if (m.feed <= 0) throw InputError({o.gcode, m.line, "F"}, "a cutting move before any F word: no feed to predict with");
    minutes += path_length(m) / m.feed;
    t.rows.push_back({double(m.line), m.end[0], m.end[1], m.end[2], minutes, o.speed, m.feed, std::abs(m.end[0]),
                      std::abs(m.end[1]), std::abs(m.end[2])});
    t.lines.push_back(m.line);
  }
  if (t.rows.empty())
    throw InputError({o.gcode, 0, ""}, "the program has no cutting move (G1, G2, G3): nothing to predict (rapids give no points)");
  return t;
}

int run_predict(const PredictOptions& o) {
  if (o.points.empty() == o.gcode.empty()) throw InputError({"predict", 0, ""}, "expected exactly one of --points, --gcode");
  check_outputs({o.model, o.points, o.gcode}, {o.out, o.compensation, o.report});
  for (const auto* p : {&o.out, &o.compensation, &o.report})
    if (!p->empty()) AtomicFile check(*p);
  const PredictionModel m = read_prediction_model(o.model);
  PointTable t;
  if (!o.points.empty()) {
    const CsvTable c = read_csv(o.points);
    if (c.rows.empty())
      throw InputError({o.points, 0, "rows"}, "expected at least one point (a row after the header), found none");
    t = {c.columns, c.rows, c.lines, o.points};
  } else {
    t = points_from_gcode(o);
  }
  std::map<std::string, double> constants;
  for (const auto& item : split_list(o.set)) {
    const auto eq = item.find('=');
    const auto v = eq == std::string::npos ? std::nullopt : parse_number(item.substr(eq + 1));
    if (!v || eq == 0) throw InputError({"--set", 0, item}, "expected NAME=VALUE items separated by commas, found '" + item + "'");
    constants[item.substr(0, eq)] = *v;
  }
  // Every variable the model reads must be a column or a --set constant: checked before any work.
  std::map<std::string, int> col;
  for (std::size_t i = 0; i < t.columns.size(); ++i) col[t.columns[i]] = static_cast<int>(i);
  for (const auto& v : m.variables())
    if (!col.count(v) && !constants.count(v)) {
      std::string users;
      for (const auto& c : m.components)
        if (c.variable == v || c.times == v || (c.ramp && c.ramp->variable == v) || (!c.stages.empty() && c.speed_variable == v))
          users += (users.empty() ? "" : ", ") + c.name;
      throw InputError({t.source, 0, v}, fmt::format("missing column '{}' needed by {} (give it as a column or with --set {}=VALUE)", v, users, v));
    }
  std::vector<PointPrediction> preds;
  std::vector<std::string> warnings;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    auto lookup = [&](const std::string& name) {
      const auto it = col.find(name);
      return it != col.end() ? t.rows[r][static_cast<std::size_t>(it->second)] : constants.at(name);
    };
    preds.push_back(predict_point(m, lookup, o.strict, fmt::format("{}:{}", t.source, t.lines[r])));
    for (const auto& w : preds.back().warnings) warnings.push_back(fmt::format("line {}: {}", t.lines[r], w));
  }
  const int step_col = col.count("step") ? col["step"] : -1;

  // Compensation per step (Table 6.1 style): the offset to add to the programmed dimension is
  // minus the mean predicted error of the step's points.
  std::vector<std::pair<double, std::array<double, 4>>> comp;  // step, sum x y z, count
  if (!o.compensation.empty()) {
    if (step_col < 0) throw InputError({t.source, 0, "step"}, "--compensation needs a 'step' column in the points");
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const double s = t.rows[r][static_cast<std::size_t>(step_col)];
      auto it = std::find_if(comp.begin(), comp.end(), [&](const auto& c) { return c.first == s; });
      if (it == comp.end()) it = comp.insert(comp.end(), {s, {0, 0, 0, 0}});
      for (int a = 0; a < 3; ++a) it->second[static_cast<std::size_t>(a)] += preds[r].e[a];
      it->second[3] += 1;
    }
    AtomicFile f(o.compensation);
    f.stream() << "step,offset_x,offset_y,offset_z\n";
    for (const auto& [s, v] : comp)
      f.stream() << fmt::format("{:g},{:.9g},{:.9g},{:.9g}\n", s, -v[0] / v[3], -v[1] / v[3], -v[2] / v[3]);
    f.commit();
  }
  if (!o.out.empty()) {
    AtomicFile f(o.out);
    std::string head;
    for (const auto& c : t.columns) head += c + ",";
    for (const auto& c : m.components) head += c.name + ",";
    f.stream() << head << "ex,ey,ez\n";
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      std::string line;
      for (double v : t.rows[r]) line += fmt::format("{:.10g},", v);
      for (double v : preds[r].values) line += fmt::format("{:.9g},", v);
      f.stream() << line << fmt::format("{:.9g},{:.9g},{:.9g}\n", preds[r].e[0], preds[r].e[1], preds[r].e[2]);
    }
    f.commit();
  }
  if (!o.report.empty()) {
    Report rep("Workpiece error prediction: " + (m.name.empty() ? o.model : m.name), command_line());
    rep.add_input("model", o.model);
    rep.add_input(o.gcode.empty() ? "points" : "G-code", t.source);
    rep.add_figure("points", fmt::format("{}", t.rows.size()), "");
    for (std::size_t i = 0; i < warnings.size() && i < 50; ++i) rep.add_warning(warnings[i]);
    if (warnings.size() > 50) rep.add_warning(fmt::format("... and {} more warnings", warnings.size() - 50));
    for (int a = 0; a < 3; ++a) {
      const char ax = static_cast<char>('x' + a);
      rep.add_section(fmt::format("{} error and its components", static_cast<char>('X' + a)));
      nlohmann::json data = nlohmann::json::array();
      std::vector<double> idx;
      for (std::size_t r = 0; r < preds.size(); ++r) idx.push_back(static_cast<double>(r + 1));
      std::vector<double> total;
      for (const auto& p : preds) total.push_back(p.e[a]);
      data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"name", fmt::format("total e{}", ax)}, {"x", idx}, {"y", total}});
      for (std::size_t k = 0; k < m.components.size(); ++k) {
        if (m.components[k].axis != ax) continue;
        std::vector<double> v;
        for (const auto& p : preds) v.push_back(p.values[k]);
        data.push_back({{"type", "scatter"}, {"mode", "lines"}, {"name", m.components[k].name}, {"x", idx}, {"y", v}});
      }
      rep.add_plot(fmt::format("Predicted {} error per point (mm), as the sum of its components (Figs. 6.4-6.5)", static_cast<char>('X' + a)),
                   {{"data", data}, {"layout", {{"xaxis", {{"title", {{"text", "point"}}}}}, {"yaxis", {{"title", {{"text", "mm"}}}}}}}});
    }
    rep.add_section("Every component (mm; tilts in rad)");
    std::vector<std::string> cols = {"point"};
    for (const auto& c : m.components) cols.push_back(c.name);
    for (const char* s : {"ex", "ey", "ez"}) cols.push_back(s);
    std::vector<std::vector<std::string>> rows;
    for (std::size_t r = 0; r < preds.size(); ++r) {
      std::vector<std::string> row = {fmt::format("{}", r + 1)};
      for (double v : preds[r].values) row.push_back(g6(v));
      for (int a = 0; a < 3; ++a) row.push_back(g6(preds[r].e[a]));
      rows.push_back(row);
    }
    rep.add_table("Components per point (Tables 6.3-6.7)", cols, rows);
    rep.write(o.report);
  }

  if (o.json_out) {
    json j;
    j["model"] = o.model;
    j["source"] = t.source;
    j["components"] = json::array();
    for (const auto& c : m.components)
      j["components"].push_back({{"name", c.name}, {"axis", c.axis ? std::string(1, c.axis) : std::string("none")}, {"source", c.source}});
    j["points"] = json::array();
    for (std::size_t r = 0; r < preds.size(); ++r) {
      json in = json::object(), comps = json::object();
      for (std::size_t k = 0; k < t.columns.size(); ++k) in[t.columns[k]] = t.rows[r][k];
      for (std::size_t k = 0; k < m.components.size(); ++k) comps[m.components[k].name] = preds[r].values[k];
      j["points"].push_back({{"line", t.lines[r]}, {"input", in}, {"components", comps},
                             {"ex", preds[r].e[0]}, {"ey", preds[r].e[1]}, {"ez", preds[r].e[2]}});
    }
    j["warnings"] = warnings;
    if (!comp.empty()) {
      j["compensation"] = json::array();
      for (const auto& [s, v] : comp)
        j["compensation"].push_back({{"step", s}, {"offset_x", -v[0] / v[3]}, {"offset_y", -v[1] / v[3]}, {"offset_z", -v[2] / v[3]}});
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{} points, {} components ({})\n", preds.size(), m.components.size(), m.name);
  std::cout << fmt::format("{:>6} {:>12} {:>12} {:>12}\n", "line", "ex (mm)", "ey (mm)", "ez (mm)");
  for (std::size_t r = 0; r < preds.size(); ++r)
    std::cout << fmt::format("{:>6} {:>12.6f} {:>12.6f} {:>12.6f}\n", t.lines[r], preds[r].e[0], preds[r].e[1], preds[r].e[2]);
  for (const auto& w : warnings) std::cout << "warning: " << w << "\n";
  if (!o.out.empty()) std::cout << "points with every component written to " << o.out << "\n";
  if (!o.compensation.empty()) std::cout << "compensation offsets per step written to " << o.compensation << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

// ---------------------------------------------------------------- separate
struct SeparateOptions {
  std::string kind, data, a, b, model, out;
  bool json_out = false;
};

int run_separate(const SeparateOptions& o) {
  check_outputs({o.data, o.model}, {o.out});
  if (!o.out.empty()) AtomicFile check(o.out);
  const TextTable t = read_text_csv(o.data);
  json j;
  j["file"] = o.data;
  j["kind"] = o.kind;
  std::vector<std::string> warnings;
  std::string csv;
  if (o.kind == "position") {
    const auto steps = separate_position(t, o.data);
    j["steps"] = json::array();
    csv = "axis,step,distance,e_pos,count\n";
    for (const auto& s : steps) {
      j["steps"].push_back({{"axis", std::string(1, s.axis)}, {"step", s.step}, {"distance", s.distance}, {"e_pos", s.e_pos}, {"count", s.count}});
      csv += fmt::format("{},{},{:g},{:.9g},{}\n", s.axis, s.step, s.distance, s.e_pos, s.count);
    }
    // The thesis' regressions (eq. 5.1-5.3): quadratic through zero for X and Y, line for Z.
    j["fits"] = json::object();
    for (char ax : {'X', 'Y', 'Z'}) {
      std::vector<double> d, e;
      for (const auto& s : steps)
        if (s.axis == ax) {
          d.push_back(s.distance);
          e.push_back(s.e_pos);
        }
      const ModelSpec spec = ax == 'Z' ? ModelSpec{ModelForm::Polynomial, 1, std::nullopt} : ModelSpec{ModelForm::Polynomial, 2, 0.0};
      if (d.size() < 3) continue;
      const FitResult f = fit_model(spec, d, e);
      j["fits"][std::string("e_pos_") + static_cast<char>(std::tolower(ax))] = fit_json(f);
    }
  } else {
    if (o.a.empty() || o.b.empty()) throw InputError({"--a", 0, ""}, "separate control needs --a and --b (workpiece names)");
    const auto rec = read_dimension_table(t, o.data);
    std::map<std::pair<int, char>, double> sub;
    if (!o.model.empty()) {
      // Eq. 3.15: subtract e_ctrl(2400-100) of the model, by the path of predict (scale,
      // validity range, stages ...) at the nominal distance and with the feed ramp at its
      // 'one_at' end (the 2400 -> 100 change the forms were fitted to, eq. 5.52-5.53).
      const PredictionModel m = read_prediction_model(o.model);
      for (const auto& r : rec) {
        if (r.workpiece != o.a) continue;
        const std::string name = r.axis == 'X' ? "e_ctrl_x" : "e_ctrl_y";
        const ErrorComponent* c = m.find(name);
        if (!c) throw InputError({o.model, 0, name}, "the model has no component '" + name + "' (eq. 5.52-5.53)");
        const auto lookup = [&](const std::string& v) -> double {
          if (v == c->variable) return r.nominal;
          if (c->ramp && v == c->ramp->variable) return c->ramp->one_at;
          throw InputError({o.model, c->line, v},
                           fmt::format("{} reads '{}': separate control gives only its distance ({}) and its feed ramp", name, v, c->variable));
        };
        const ComponentValue v = evaluate_component(m, name, lookup, false, fmt::format("{}:{}", o.data, r.line));
        for (const auto& w : v.warnings) warnings.push_back(fmt::format("line {}: {}", r.line, w));
        sub[{r.step, r.axis}] = v.value;
      }
    }
    const auto steps = separate_control(rec, o.a, o.b, o.data, sub);
    const std::string what = o.model.empty() ? "e_ctrl" : "e_cpr";
    j["quantity"] = what;
    j["a"] = o.a;
    j["b"] = o.b;
    j["steps"] = json::array();
    csv = "axis,step,distance," + what + "\n";
    for (const auto& s : steps) {
      j["steps"].push_back({{"axis", std::string(1, s.axis)}, {"step", s.step}, {"distance", s.distance}, {what, s.value}});
      csv += fmt::format("{},{},{:g},{:.9g}\n", s.axis, s.step, s.distance, s.value);
    }
  }
  if (!o.out.empty()) write_file_atomically(o.out, csv);
  if (o.kind == "control") j["warnings"] = warnings;
  if (o.json_out) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << csv;
  for (const auto& w : warnings) std::cout << "warning: " << w << "\n";
  if (j.contains("fits"))
    for (const auto& [name, f] : j["fits"].items()) {
      std::string p;
      for (const auto& [k, v] : f["parameters"].items()) p += fmt::format(" {}={}", k, v["value"].is_null() ? std::string("-") : g6(v["value"].get<double>()));
      std::cout << fmt::format("{} = {}:{}\n", name, f["model"].get<std::string>(), p);
    }
  if (!o.out.empty()) std::cout << "written to " << o.out << "\n";
  return 0;
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
      throw InputError({"--measured", 0, ""}, fmt::format("expected one measured process error per feed ({}), found {}", feeds.size(),
                                                          measured.size()));
    const auto specs = parse_model_specs(o.form, "--form");
    if (specs.size() != 1) throw InputError({"--form", 0, o.form}, "expected one model form for the calibration, found " + o.form);
    spec = specs[0];
  }
  struct Row {
    double feed, fz;
    MillingForces f;
    double e_prog;
  };
  std::vector<Row> rows;
  for (double F : feeds) {
    CutConditions c = o.cut;
    c.feed = F;
    Row r{F, F / (o.tool.teeth * c.spindle_speed), milling_forces(o.tool, o.k, c), 0.0};
    r.e_prog = program_generated_error(o.tool, o.k, c);
    rows.push_back(std::move(r));
  }
  std::optional<Calibration> cal;
  if (spec) {
    cal = calibrate_process_error(o.tool, o.k, o.cut, feeds, measured, *spec);
    if (!cal->fit.converged) throw Error("the calibration " + spec->label() + " did not converge: " + cal->fit.message);
  }
  if (o.json_out) {
    json j;
    j["tool"] = {{"diameter", o.tool.diameter}, {"teeth", o.tool.teeth}, {"helix_deg", o.tool.helix_deg},
                 {"overhang", o.tool.overhang}, {"flute_length", o.tool.flute_length},
                 {"flute_diameter_ratio", o.tool.flute_diameter_ratio}, {"young_modulus", o.tool.young_modulus}};
    j["coefficients"] = {{"ktc", o.k.ktc}, {"krc", o.k.krc}, {"kte", o.k.kte}, {"kre", o.k.kre}};
    j["cut"] = {{"radial_depth", o.cut.radial_depth}, {"axial_depth", o.cut.axial_depth}, {"spindle_speed", o.cut.spindle_speed},
                {"down_milling", o.cut.down_milling}};
    j["points"] = json::array();
    for (const auto& r : rows)
      j["points"].push_back({{"feed", r.feed}, {"fz", r.fz}, {"mean_fx", r.f.mean_x}, {"mean_fy", r.f.mean_y},
                             {"peak_fy", r.f.peak_y}, {"e_prog", r.e_prog}});
    if (cal) {
      json c = fit_json(cal->fit);
      c["measured"] = measured;
      j["calibration"] = c;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("tool D {:g} mm, {} teeth, helix {:g} deg, overhang {:g} mm, flutes {:g} mm at {:g} D, E {:g} N/mm^2\n",
                           o.tool.diameter, o.tool.teeth, o.tool.helix_deg, o.tool.overhang, o.tool.flute_length,
                           o.tool.flute_diameter_ratio, o.tool.young_modulus);
  std::cout << fmt::format("cut ae {:g} mm, ap {:g} mm, {:g} rpm, {} milling; Ktc {:g} Krc {:g} N/mm^2, Kte {:g} Kre {:g} N/mm\n",
                           o.cut.radial_depth, o.cut.axial_depth, o.cut.spindle_speed, o.cut.down_milling ? "down" : "up", o.k.ktc,
                           o.k.krc, o.k.kte, o.k.kre);
  std::cout << fmt::format("{:>10} {:>12} {:>12} {:>12} {:>12} {:>14}\n", "F (mm/min)", "fz (mm)", "mean Fx (N)", "mean Fy (N)",
                           "peak |Fy| (N)", "e_prog (mm)");
  for (const auto& r : rows)
    std::cout << fmt::format("{:>10g} {:>12.6g} {:>12.6g} {:>12.6g} {:>12.6g} {:>14.6g}\n", r.feed, r.fz, r.f.mean_x, r.f.mean_y,
                             r.f.peak_y, r.e_prog);
  if (cal) {
    const auto& f = cal->fit;
    std::cout << fmt::format("calibration measured = {}(e_prog) (eq. 5.49-5.51): {}\n", f.model.spec.label(), params_text(f));
    std::cout << fmt::format("  RSS {}  R^2 {}  backward mean |diff| {}  max {}\n", g6(f.rss), g6(f.r_squared), g6(f.backward.mean),
                             g6(f.backward.max));
  }
  return 0;
}

}  // namespace

std::vector<Command> add_prediction_commands(CLI::App& app) {
  auto ro = std::make_shared<RegressOptions>();
  auto* r = app.add_subcommand("regress",
                               "Fit the regression forms of Yaqoob 2017 (polynomial, exp_approach, stretched_exp, logistic_ln, "
                               "gompertz, saturation, power) to y(x) with uncertainties; rank by backward-prediction error "
                               "(sec. 3.8) and by leave-one-out cross-validation");
  r->add_option("DATA", ro->data, "CSV with a header; the columns --x and --y are used")->required();
  r->add_option("--x", ro->x, "Column of the driving variable (e.g. t)")->required();
  r->add_option("--y", ro->y, "Column of the error (e.g. e)")->required();
  r->add_option("--models", ro->models, "all, or a comma list: polynomial(1..3), polynomial(2,c0=0), exp_approach, ...")->capture_default_str();
  r->add_flag("--json", ro->json_out, "Machine-readable output: file x y n fits[] (model form parameters{value,stddev} rss sigma dof "
                                      "r_squared aicc backward{mean,max,mean_relative,abs_diff} loocv_rmse) skipped[] best_backward best_loocv");
  r->add_option("--report", ro->report, "Write an HTML report: data with every fitted curve, table of criteria");

  auto po = std::make_shared<PredictOptions>();
  auto* p = app.add_subcommand("predict",
                               "Predict the X, Y, Z errors of a workpiece from a prediction model (Yaqoob 2017 ch. 6): every "
                               "component per point and their sums; compensation offsets per step");
  p->add_option("--model", po->model, "Prediction model YAML (docs/prediction.md)")->required();
  p->add_option("--points", po->points, "CSV of points: a column per variable the model reads (t, S, F, dx, dy, dz ...), optional step");
  p->add_option("--gcode", po->gcode, "Or a G-code program: a point per move end (needs --speed; --start-time)");
  p->add_option("--start-time", po->start_time, "Minutes since machine start at the program's first block (--gcode)")->check(kFinite);
  p->add_option("--speed", po->speed, "Spindle speed for --gcode (rpm)")->check(kFinite);
  p->add_option("--rapid-feed", po->rapid_feed, "Feed of G0 moves for the time stamps (mm/min)")->check(CLI::PositiveNumber)->capture_default_str();
  p->add_option("--set", po->set, "Constant variables not in the points, e.g. \"h_tt=10,h_spd=9\"");
  p->add_flag("--strict", po->strict, "Refuse a point outside a component's validity range (default: extrapolate with a warning)");
  p->add_option("--out", po->out, "Write the points with every component and ex, ey, ez to this CSV");
  p->add_option("--compensation", po->compensation, "Write offsets per step (step,offset_x,offset_y,offset_z = -mean predicted error)");
  p->add_flag("--json", po->json_out, "Machine-readable output: model source components[] (name axis source) points[] (line input "
                                      "components ex ey ez) warnings[] compensation[]");
  p->add_option("--report", po->report, "Write an HTML report: components per point and axis, table");

  auto so = std::make_shared<SeparateOptions>();
  auto* s = app.add_subcommand("separate",
                               "Separate error components from measured workpieces (Yaqoob 2017 sec. 3.3-3.6): position errors "
                               "(CMM - probe per step, with eq. 5.1-5.3 fits) or control errors between two workpieces (eq. 3.11-3.15)");
  s->add_option("KIND", so->kind, "position or control")->required()->check(CLI::IsMember({"position", "control"}));
  s->add_option("DATA", so->data, "position: step,d_x,d_y,d_z,cmm_<F>,probe_<F>...; control: workpiece,step,axis,nominal,measured,e_pf,e_pt,e_pos")
      ->required();
  s->add_option("--a", so->a, "control: first workpiece (e.g. W2)");
  s->add_option("--b", so->b, "control: second workpiece (W8 for e_ctrl, eq. 3.11-3.12; W5 with --model for e_cpr, eq. 3.15)");
  s->add_option("--model", so->model, "control: prediction model whose e_ctrl_x / e_ctrl_y (eq. 5.52-5.53) are subtracted (eq. 3.15)");
  s->add_option("--out", so->out, "Write the separated values as CSV");
  s->add_flag("--json", so->json_out, "Machine-readable output: file kind steps[] (axis step distance e_pos count | e_ctrl/e_cpr) fits{}");

  auto eo = std::make_shared<ProcessErrorOptions>();
  auto* e = app.add_subcommand("process-error",
                               "Program-generated process error e_prog (Yaqoob 2017 sec. 3.7): mechanistic milling forces and the "
                               "tool as a two-section cantilever, per feed; with --measured, the calibration measured = f(e_prog) "
                               "(eq. 5.49-5.51)");
  e->add_option("--feed", eo->feeds, "Feed(s) F (mm/min), a comma list, e.g. \"100,200,400,800,1600\"")->required();
  e->add_option("--speed", eo->cut.spindle_speed, "Spindle speed S (rpm)")->check(CLI::PositiveNumber)->capture_default_str();
  e->add_option("--ae", eo->cut.radial_depth, "Radial depth of cut (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--ap", eo->cut.axial_depth, "Axial depth of cut (mm)")->check(kFinite)->capture_default_str();
  e->add_flag("--up-milling", eo->up_milling, "Up (conventional) milling (default: down / climb milling)");
  e->add_option("--diameter", eo->tool.diameter, "Tool diameter D (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--teeth", eo->tool.teeth, "Number of teeth")->capture_default_str();
  e->add_option("--helix", eo->tool.helix_deg, "Helix angle (deg; 0: straight flutes)")->check(kFinite)->capture_default_str();
  e->add_option("--overhang", eo->tool.overhang, "Length out of the holder L (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--flute-length", eo->tool.flute_length, "Fluted length from the tip (mm)")->check(kFinite)->capture_default_str();
  e->add_option("--flute-ratio", eo->tool.flute_diameter_ratio, "Equivalent diameter of the fluted section / D")
      ->check(kFinite)
      ->capture_default_str();
  e->add_option("--young", eo->tool.young_modulus, "Young's modulus E (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--ktc", eo->k.ktc, "Tangential cutting coefficient (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--krc", eo->k.krc, "Radial cutting coefficient (N/mm^2)")->check(kFinite)->capture_default_str();
  e->add_option("--kte", eo->k.kte, "Tangential edge coefficient (N/mm)")->check(kFinite)->capture_default_str();
  e->add_option("--kre", eo->k.kre, "Radial edge coefficient (N/mm)")->check(kFinite)->capture_default_str();
  e->add_option("--measured", eo->measured, "Measured process errors (mm), one per feed: calibrate measured = f(e_prog)");
  e->add_option("--form", eo->form, "Calibration form: logistic_ln (eq. 5.49-5.50), saturation (eq. 5.51) or any regress form")
      ->capture_default_str();
  e->add_flag("--json", eo->json_out, "Machine-readable output: tool coefficients cut points[] (feed fz mean_fx mean_fy peak_fy e_prog) "
                                      "calibration (a regress fit with measured[])");
  return {{r, [ro] { return run_regress(*ro); }},
          {p, [po] { return run_predict(*po); }},
          {s, [so] { return run_separate(*so); }},
          {e, [eo] { return run_process_error(*eo); }}};
}

}  // namespace mtcal::cli
