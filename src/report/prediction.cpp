// HTML reports of regress and predict: fitted curves and criteria; predicted errors by component.
#include "mtcal/report/prediction.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

std::string significant6(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string("-"); }

std::string fit_parameters_text(const FitResult& f) {
  std::string s;
  const auto names = parameter_names(f.model.spec);
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::string note;
    if (k < f.at_bound.size() && f.at_bound[k])
      note = " (at bound)";
    else if (k < f.identified.size() && !f.identified[k])
      note = " (not identifiable)";
    else if (std::isfinite(f.stddev[k]))
      note = "±" + significant6(f.stddev[k]);
    s += fmt::format("{}{}={}{}", s.empty() ? "" : " ", names[k], significant6(f.model.p[k]), note);
  }
  return s;
}

TableRegression regress_table(const CsvTable& t, const std::string& source, const std::string& x_name,
                         const std::string& y_name, const std::vector<ModelSpec>& specs) {
  const int cx = t.column(x_name), cy = t.column(y_name);
  if (cx < 0) throw InputError({source, 0, x_name}, "no column '" + printable(x_name) + "' (--x)");
  if (cy < 0) throw InputError({source, 0, y_name}, "no column '" + printable(y_name) + "' (--y)");
  TableRegression g;
  for (const auto& row : t.rows) {
    g.x.push_back(row[static_cast<std::size_t>(cx)]);
    g.y.push_back(row[static_cast<std::size_t>(cy)]);
  }
  if (g.x.size() < 2)
    throw InputError({source, 0, y_name}, fmt::format("expected at least 2 rows, found {}", g.x.size()));
  g.comparison = compare_models(specs, g.x, g.y);
  if (g.comparison.fits.empty())
    throw Error("no model could be fitted: " +
                (g.comparison.skipped.empty() ? std::string() : g.comparison.skipped[0].reason));
  return g;
}

Report regression_report(const ModelComparison& c, std::span<const double> x, std::span<const double> y,
                         const std::string& file, const std::string& x_name, const std::string& y_name,
                         const std::string& command) {
  return regression_report(c, x, y, file, file.empty() ? "" : sha256_hex(read_text_file(file, "data")), x_name,
                           y_name, command, session_metadata());
}

Report regression_report(const ModelComparison& c, std::span<const double> x, std::span<const double> y,
                         const std::string& file, const std::string& file_sha256, const std::string& x_name,
                         const std::string& y_name, const std::string& command, const ReportMetadata& metadata) {
  const FitResult& bb = c.fits[c.by_backward[0]];
  const FitResult& bl = c.fits[c.by_loocv[0]];
  Report r("Regression: " + y_name + " vs " + x_name, command);
  r.set_metadata(metadata);
  if (!file.empty()) r.add_input("data", file, file_sha256);
  r.add_figure("points", fmt::format("{}", x.size()), "");
  r.add_figure("best by backward prediction (sec. 3.8)", bb.model.spec.label(),
               fmt::format("mean |diff| {}", significant6(bb.backward.mean)));
  r.add_figure("best by leave-one-out", bl.model.spec.label(),
               bl.loocv_rmse ? "RMSE " + significant6(*bl.loocv_rmse) : "");
  for (const auto& s : c.skipped) r.add_warning(s.spec.label() + " not fitted: " + s.reason);
  r.add_section("Data and fitted models");
  nlohmann::json data = nlohmann::json::array();
  data.push_back({{"type", "scatter"},
                  {"mode", "markers"},
                  {"name", "data"},
                  {"x", std::vector<double>(x.begin(), x.end())},
                  {"y", std::vector<double>(y.begin(), y.end())}});
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
             {{"data", data},
              {"layout", {{"xaxis", {{"title", {{"text", x_name}}}}}, {"yaxis", {{"title", {{"text", y_name}}}}}}}});
  r.add_section("Criteria");
  r.add_paragraph(
      "Backward-prediction error (Yaqoob 2017 section 3.8, Table 5.8): |y - f(x)| at the measured points of "
      "the model fitted to all of them; ranked by its mean. It is an in-sample criterion and favours models "
      "with more parameters; the leave-one-out RMSE predicts each point from a refit without it.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& f : c.fits)
    rows.push_back({f.model.spec.label(), fit_parameters_text(f), significant6(f.rss), significant6(f.r_squared),
                    significant6(f.backward.mean), significant6(f.backward.max),
                    f.loocv_rmse ? significant6(*f.loocv_rmse) : "-", significant6(f.aicc)});
  r.add_table("Fitted models (parameters ± standard uncertainty)",
              {"model", "parameters", "RSS", "R²", "mean backward |diff|", "max backward |diff|", "LOO RMSE", "AICc"},
              rows);
  return r;
}

Report prediction_report(const PredictionRun& run, const PredictionModel& m, const std::string& model_file,
                         const std::string& points_label, const std::string& command) {
  const auto& preds = run.predictions;
  const auto& warnings = run.warnings;
  Report rep("Workpiece error prediction: " + (m.name.empty() ? model_file : m.name), command);
  rep.add_input("model", model_file);
  rep.add_input(points_label, run.points.source);
  rep.add_figure("points", fmt::format("{}", run.points.rows.size()), "");
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
    data.push_back({{"type", "scatter"},
                    {"mode", "lines+markers"},
                    {"name", fmt::format("total e{}", ax)},
                    {"x", idx},
                    {"y", total}});
    for (std::size_t k = 0; k < m.components.size(); ++k) {
      if (m.components[k].axis != ax) continue;
      std::vector<double> v;
      for (const auto& p : preds) v.push_back(p.values[k]);
      data.push_back({{"type", "scatter"}, {"mode", "lines"}, {"name", m.components[k].name}, {"x", idx}, {"y", v}});
    }
    rep.add_plot(fmt::format("Predicted {} error per point (mm), as the sum of its components (Figs. 6.4-6.5)",
                             static_cast<char>('X' + a)),
                 {{"data", data},
                  {"layout", {{"xaxis", {{"title", {{"text", "point"}}}}}, {"yaxis", {{"title", {{"text", "mm"}}}}}}}});
  }
  rep.add_section("Every component (mm; tilts in rad)");
  std::vector<std::string> cols = {"point"};
  for (const auto& c : m.components) cols.push_back(c.name);
  for (const char* s : {"ex", "ey", "ez"}) cols.push_back(s);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t r = 0; r < preds.size(); ++r) {
    std::vector<std::string> row = {fmt::format("{}", r + 1)};
    for (double v : preds[r].values) row.push_back(significant6(v));
    for (int a = 0; a < 3; ++a) row.push_back(significant6(preds[r].e[a]));
    rows.push_back(row);
  }
  rep.add_table("Components per point (Tables 6.3-6.7)", cols, rows);
  return rep;
}

}  // namespace mtcal
