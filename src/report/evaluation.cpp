// HTML reports of the acceptance-test evaluations (report/evaluation.hpp).
#include "mtcal/report/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/report/report.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

using json = nlohmann::ordered_json;

// Numbers for people: 5 significant digits whatever the input's unit; "-" where there is none.
std::string num(const std::optional<double>& v) { return v ? fmt::format("{:.5g}", *v) : std::string("-"); }
std::string yes_no(const std::optional<bool>& v) { return v ? (*v ? "yes" : "no") : "-"; }
std::string r_text(const std::optional<double>& v) { return v ? fmt::format("{:.3f}", *v) : std::string("-"); }

}  // namespace

std::string PositioningDisplay::format(double v) const {
  if (v != v) return "n/a";
  return fmt::format("{:.{}f}", v * factor, decimals);
}

PositioningDisplay positioning_display(const PositioningRuns& runs, const PositioningEvaluation& e) {
  PositioningDisplay d;
  d.unit = e.unit;
  if (e.unit == "mm") d.unit = "um", d.factor = 1e3;
  // Decimals that write every input value exactly, in the unit shown.
  std::vector<double> deviations;
  int resolved = 0;
  for (std::size_t i = 0; i < runs.targets.size(); ++i)
    for (const auto* side : {&runs.up[i], &runs.down[i]})
      for (double v : *side) {
        const double x = (runs.deviations ? v : v - runs.targets[i]) * d.factor;
        const double shown = v * d.factor;
        deviations.push_back(std::abs(x));
        int k = 0;
        while (k < 6 && std::abs(shown * std::pow(10.0, k) - std::round(shown * std::pow(10.0, k))) >
                            1e-6 * std::max(1.0, std::abs(shown * std::pow(10.0, k))))
          ++k;
        resolved = std::max(resolved, k);
      }
  // Two significant digits of the scatter: the median standard deviation (or a tenth of the
  // median deviation with a single run).
  std::vector<double> s;
  for (const auto& t : e.targets)
    for (double v : {t.s_up, t.s_down})
      if (v == v && v > 0) s.push_back(v * d.factor);
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
  };
  double scale = s.empty() ? median(deviations) / 10 : median(s);
  int noise = 6;
  if (scale > 0) noise = std::clamp(1 - static_cast<int>(std::floor(std::log10(scale))), 0, 6);
  // Means and spreads resolve one digit more than the values they come from.
  d.decimals = std::min(resolved + 1, noise);
  return d;
}

std::string positioning_text(const PositioningRuns& runs, const PositioningEvaluation& e) {
  const PositioningDisplay d = positioning_display(runs, e);
  auto f = [&](double v) { return d.format(v); };
  const std::string tu = e.target_unit.empty() ? e.unit : e.target_unit;
  std::string s;
  s += fmt::format("ISO 230-2: {} targets x {} runs per direction{}; deviations in {}\n", e.targets.size(), e.runs,
                   e.directions == TestDirections::Both     ? ""
                   : e.directions == TestDirections::UpOnly ? " (unidirectional, up)"
                                                            : " (unidirectional, down)",
                   d.unit);
  s += fmt::format("{:>12} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "target " + tu, "mean_up", "mean_down",
                   "B_i", "s_up", "s_down", "R_i", "mean");
  for (const auto& t : e.targets)
    s += fmt::format("{:>12g} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", t.target, f(t.mean_up),
                     f(t.mean_down), f(t.reversal), f(t.s_up), f(t.s_down), f(t.R), f(t.mean));
  s += fmt::format("A {} (up {}, down {})   R {} (up {}, down {})\n", f(e.A), f(e.A_up), f(e.A_down), f(e.R), f(e.R_up),
                   f(e.R_down));
  s += fmt::format("B {} (mean {})   E {} (up {}, down {})   M {}   [{}]\n", f(e.B), f(e.B_mean), f(e.E), f(e.E_up),
                   f(e.E_down), f(e.M), d.unit);
  for (const auto& n : e.notes) s += "note: " + n + "\n";
  return s;
}

void write_positioning_report(const std::string& path, const std::string& command, const PositioningRuns& runs,
                              const PositioningEvaluation& e) {
  const auto target_unit = find_unit(e.target_unit.empty() ? e.unit : e.target_unit);
  const bool rotary = target_unit && target_unit->dimension == Dimension::Angle;
  Report r(rotary ? "ISO 230-2 positioning of a rotary axis" : "ISO 230-2 positioning of a linear axis", command);
  r.add_input("measurements", runs.source);
  const PositioningDisplay shown = positioning_display(runs, e);
  const std::string u = shown.unit;
  const bool has_up = e.directions != TestDirections::DownOnly, has_down = e.directions != TestDirections::UpOnly;
  const bool both = has_up && has_down;
  r.add_figure(both     ? "accuracy A"
               : has_up ? "accuracy A↑"
                        : "accuracy A↓",
               shown.format(both     ? e.A
                            : has_up ? e.A_up
                                     : e.A_down),
               u);
  r.add_figure(both     ? "repeatability R"
               : has_up ? "repeatability R↑"
                        : "repeatability R↓",
               shown.format(both     ? e.R
                            : has_up ? e.R_up
                                     : e.R_down),
               u);
  if (both) r.add_figure("reversal value B", shown.format(e.B), u);
  r.add_figure(both     ? "systematic positioning error E"
               : has_up ? "systematic positioning error E↑"
                        : "systematic positioning error E↓",
               shown.format(both     ? e.E
                            : has_up ? e.E_up
                                     : e.E_down),
               u);
  if (both) r.add_figure("mean positioning error M", shown.format(e.M), u);
  r.add_figure("targets x runs", fmt::format("{} x {}", e.targets.size(), e.runs), "per direction");
  for (const auto& n : e.notes) r.add_warning(n);
  for (const auto& w : runs.warnings) r.add_warning(w);

  r.add_section("Deviations");
  r.add_paragraph(
      "Mean positional deviation per target and direction (x̄↑ up, x̄↓ down) with the ±2s bands that "
      "define the accuracy A, and every run's deviation as a point.");
  json x = json::array(), up = x, dn = x, up_hi = x, up_lo = x, dn_hi = x, dn_lo = x, mean = x;
  json rx_up = x, ry_up = x, rx_dn = x, ry_dn = x;
  const double k = shown.factor;
  const std::string tu = e.target_unit.empty() ? e.unit : e.target_unit;
  for (std::size_t i = 0; i < e.targets.size(); ++i) {
    const auto& t = e.targets[i];
    x.push_back(t.target);
    up.push_back(k * t.mean_up);
    dn.push_back(k * t.mean_down);
    mean.push_back(k * t.mean);
    up_hi.push_back(k * (t.mean_up + 2 * t.s_up));
    up_lo.push_back(k * (t.mean_up - 2 * t.s_up));
    dn_hi.push_back(k * (t.mean_down + 2 * t.s_down));
    dn_lo.push_back(k * (t.mean_down - 2 * t.s_down));
    const double off = runs.deviations ? 0.0 : t.target;
    for (double v : runs.up[i]) rx_up.push_back(t.target), ry_up.push_back(k * (v - off));
    for (double v : runs.down[i]) rx_dn.push_back(t.target), ry_dn.push_back(k * (v - off));
  }
  auto band = [&](const json& lo, const json& hi, const char* colour, const char* name) {
    return json::array({json{{"type", "scatter"},
                             {"mode", "lines"},
                             {"x", x},
                             {"y", lo},
                             {"line", {{"width", 0}}},
                             {"showlegend", false},
                             {"hoverinfo", "skip"}},
                        json{{"type", "scatter"},
                             {"mode", "lines"},
                             {"x", x},
                             {"y", hi},
                             {"fill", "tonexty"},
                             {"fillcolor", colour},
                             {"line", {{"width", 0}}},
                             {"name", name}}});
  };
  json data = json::array();
  for (auto& t : band(up_lo, up_hi, "rgba(31,119,180,0.2)", "x̄↑ ± 2s↑")) data.push_back(t);
  for (auto& t : band(dn_lo, dn_hi, "rgba(214,39,40,0.2)", "x̄↓ ± 2s↓")) data.push_back(t);
  data.push_back({{"type", "scatter"},
                  {"mode", "lines+markers"},
                  {"x", x},
                  {"y", up},
                  {"name", "x̄↑ (up)"},
                  {"line", {{"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"},
                  {"mode", "lines+markers"},
                  {"x", x},
                  {"y", dn},
                  {"name", "x̄↓ (down)"},
                  {"line", {{"color", "rgb(214,39,40)"}}}});
  data.push_back({{"type", "scatter"},
                  {"mode", "lines"},
                  {"x", x},
                  {"y", mean},
                  {"name", "x̄ (bidirectional)"},
                  {"line", {{"color", "black"}, {"dash", "dot"}}}});
  data.push_back({{"type", "scatter"},
                  {"mode", "markers"},
                  {"x", rx_up},
                  {"y", ry_up},
                  {"name", "runs up"},
                  {"marker", {{"size", 4}, {"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"},
                  {"mode", "markers"},
                  {"x", rx_dn},
                  {"y", ry_dn},
                  {"name", "runs down"},
                  {"marker", {{"size", 4}, {"color", "rgb(214,39,40)"}}}});
  r.add_plot("Positional deviation x = measured − target (" + u + ") against the target position (" + tu + ")",
             {{"data", data},
              {"layout",
               {{"xaxis", {{"title", {{"text", "target (" + tu + ")"}}}}},
                {"yaxis", {{"title", {{"text", "deviation (" + u + ")"}}}}}}}});

  r.add_section("Per target");
  std::vector<std::vector<std::string>> rows;
  for (const auto& t : e.targets)
    rows.push_back({fmt::format("{:g}", t.target), shown.format(t.mean_up), shown.format(t.mean_down),
                    shown.format(t.mean), shown.format(t.reversal), shown.format(t.s_up), shown.format(t.s_down),
                    shown.format(t.R_up), shown.format(t.R_down), shown.format(t.R)});
  r.add_table("ISO 230-2 quantities per target (" + u + ")",
              {"target", "x̄↑", "x̄↓", "x̄", "B_i", "s↑", "s↓", "R↑", "R↓", "R_i"}, rows);
  r.add_table("Axis (" + u + ")", {"A", "A↑", "A↓", "B", "B̄", "R", "R↑", "R↓", "E", "E↑", "E↓", "M"},
              {{shown.format(e.A), shown.format(e.A_up), shown.format(e.A_down), shown.format(e.B),
                shown.format(e.B_mean), shown.format(e.R), shown.format(e.R_up), shown.format(e.R_down),
                shown.format(e.E), shown.format(e.E_up), shown.format(e.E_down), shown.format(e.M)}});
  if (!runs.metadata.empty()) {
    std::vector<std::vector<std::string>> meta;
    for (const auto& [key, value] : runs.metadata) meta.push_back({key, value});
    r.add_table("What the file says beside the runs", {"key", "value"}, meta);
  }
  r.write(path);
}

void write_ballbar_report(const std::string& path, const std::string& command, const BallbarTrace& trace,
                          const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                          const std::string& plane, double radius, double feed) {
  const std::vector<TracePoint>& t = trace.points;
  Report r("ISO 230-4 circular test, plane " + plane, command);
  r.add_input("trace", trace.source);
  r.add_figure("nominal radius", fmt::format("{:g}", radius), "mm");
  if (feed > 0) r.add_figure("feed", fmt::format("{:g}", feed), "mm/min");
  if (e.cw) r.add_figure("G (CW)", fmt::format("{:.2f}", e.cw->G * 1e3), "µm");
  if (e.ccw) r.add_figure("G (CCW)", fmt::format("{:.2f}", e.ccw->G * 1e3), "µm");
  if (e.G_b) r.add_figure("G(b)", fmt::format("{:.2f}", *e.G_b * 1e3), "µm");
  if (e.H) r.add_figure("H", fmt::format("{:.2f}", *e.H * 1e3), "µm");
  r.add_figure("F max / min", fmt::format("{:.2f} / {:.2f}", e.F_max * 1e3, e.F_min * 1e3), "µm");
  r.add_section("Trace");
  r.add_paragraph(
      "Radial deviation of the bar from the nominal radius (µm), magnified round the circle, for both "
      "directions, as ballbar software shows it.");
  json data = json::array();
  for (CircleDirection d : {CircleDirection::CW, CircleDirection::CCW}) {
    json th = json::array(), rr = json::array();
    for (const auto& s : t)
      if (s.direction == d) {
        th.push_back(s.angle * 180 / std::numbers::pi);
        rr.push_back((s.radius - radius) * 1e3);
      }
    data.push_back({{"type", "scatterpolar"},
                    {"mode", "lines"},
                    {"theta", th},
                    {"r", rr},
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
                      fmt::format("{:.3f}", d->F_min * 1e3),
                      fmt::format("{:.3f}, {:.3f}", d->centre_x * 1e3, d->centre_y * 1e3)});
  r.add_table("ISO 230-4 per direction (µm)",
              {"direction", "samples", "G", "G minimum zone", "F max", "F min", "least-squares centre (µm)"}, rows);
  if (diagnosis) {
    r.add_section("Diagnostics");
    r.add_paragraph(
        fmt::format("Least-squares fit of a physical model of the trace (docs/evaluations.md); the share is "
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
  r.write(path);
}

void write_comparison_report(const std::string& path, const std::string& command, const MethodComparison& c) {
  const auto& s = c.summary;
  Report r(fmt::format("Method comparison: {} and {}", c.methods[0], c.methods[1]), command);
  r.add_input("data", c.source);
  r.add_figure("parameters", fmt::format("{}", s.parameters),
               fmt::format("({} measured by both methods)", s.both_methods));
  r.add_figure("mean ± 1σ bands overlap", fmt::format("{} of {}", s.overlap, s.overlap + s.no_overlap), "parameters");
  r.add_figure(fmt::format("|Pearson r| ≥ {:g}", kStrongCorrelation),
               fmt::format("{} of {}", s.strong_correlation, s.with_correlation),
               fmt::format("parameters ({} positive, {} negative)", s.strong_positive, s.strong_negative));
  for (const auto& p : c.parameters) {
    if (p.stats[0].n == 0 || p.stats[1].n == 0)
      r.add_warning(fmt::format("{} was measured by {} only: no difference, overlap or correlation.", p.name,
                                c.methods[p.stats[0].n > 0 ? 0 : 1]));
    else if (p.stats[0].n < 2 || p.stats[1].n < 2)
      r.add_warning(
          fmt::format("{} has fewer than two tests for one method: no standard deviation, no overlap.", p.name));
  }

  r.add_section("Means of both methods");
  nlohmann::json data = nlohmann::json::array();
  for (std::size_t k = 0; k < 2; ++k) {
    nlohmann::json x = nlohmann::json::array(), y = x, e = x;
    for (const auto& p : c.parameters) {
      x.push_back(p.name);
      y.push_back(p.stats[k].mean ? nlohmann::json(*p.stats[k].mean) : nlohmann::json(nullptr));
      e.push_back(p.stats[k].stdev.value_or(0.0));
    }
    data.push_back({{"type", "bar"},
                    {"name", c.methods[k]},
                    {"x", x},
                    {"y", y},
                    {"error_y", {{"type", "data"}, {"array", e}, {"visible", true}}}});
  }
  r.add_plot("Mean of each parameter per method, with ±1 sample standard deviation as error bars (in the data's units)",
             {{"data", data},
              {"layout", {{"barmode", "group"}, {"yaxis", {{"title", {{"text", "mean (data's units)"}}}}}}}});

  r.add_section("Every parameter");
  r.add_paragraph(
      "Standard deviations are sample standard deviations (n − 1). The ±1σ bands overlap when "
      "|difference of means| ≤ σ₁ + σ₂. Pearson r pairs the tests of the same name and needs at least "
      "three pairs in which both methods vary.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : c.parameters)
    rows.push_back({p.name, fmt::format("{}", p.stats[0].n), num(p.stats[0].mean), num(p.stats[0].stdev),
                    fmt::format("{}", p.stats[1].n), num(p.stats[1].mean), num(p.stats[1].stdev), num(p.abs_diff),
                    yes_no(p.overlap), r_text(p.pearson_r), fmt::format("{}", p.paired)});
  const std::string& a = c.methods[0];
  const std::string& b = c.methods[1];
  r.add_table("Statistics per parameter (values in the data's units)",
              {"parameter", "n " + a, "mean " + a, "stdev " + a, "n " + b, "mean " + b, "stdev " + b, "|difference|",
               "±1σ overlap", "Pearson r", "paired tests"},
              rows);
  r.write(path);
}

}  // namespace mtcal
