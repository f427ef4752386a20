// HTML reports of the acceptance-test evaluations (report/evaluation.hpp).
#include "mtcal/report/evaluation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/system/files.hpp"
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

std::vector<TableBlock> positioning_target_table(const PositioningRuns& runs, const PositioningEvaluation& e,
                                                 const PositioningDisplay& shown, std::size_t max_columns) {
  const bool has_up = e.directions != TestDirections::DownOnly, has_down = e.directions != TestDirections::UpOnly;
  const std::string tu = e.target_unit.empty() ? e.unit : e.target_unit;
  const auto& T = e.targets;
  // The tolerant reader may give targets different numbers of runs: as many rows as the most,
  // "-" where a target has fewer.
  std::size_t runs_up = 0, runs_down = 0;
  for (std::size_t i = 0; i < T.size(); ++i) {
    runs_up = std::max(runs_up, i < runs.up.size() ? runs.up[i].size() : 0);
    runs_down = std::max(runs_down, i < runs.down.size() ? runs.down[i].size() : 0);
  }
  auto f = [&](double v) { return shown.format(v); };
  auto deviation = [&](const std::vector<std::vector<double>>& side, std::size_t i, std::size_t j) {
    if (i >= side.size() || j >= side[i].size()) return std::string("-");
    return f(runs.deviations ? side[i][j] : side[i][j] - runs.targets[i]);
  };
  std::vector<TableBlock> blocks;
  // As many blocks as max_columns needs, of even width (11 targets: 6 and 5, not 10 and 1).
  max_columns = std::max<std::size_t>(max_columns, 1);
  const std::size_t n_blocks = (T.size() + max_columns - 1) / max_columns;
  const std::size_t width = n_blocks ? (T.size() + n_blocks - 1) / n_blocks : 1;
  for (std::size_t first = 0; first < T.size(); first += width) {
    const std::size_t last = std::min(T.size(), first + width);
    TableBlock b;
    b.caption = fmt::format("Deviations and statistics per target ({}), targets {} to {} of {}", shown.unit, first + 1,
                            last, T.size());
    b.columns.push_back("target i");
    for (std::size_t i = first; i < last; ++i) b.columns.push_back(fmt::format("{}", i + 1));
    auto row = [&](const std::string& label, auto&& value) {
      std::vector<std::string> r{label};
      for (std::size_t i = first; i < last; ++i) r.push_back(value(i));
      b.rows.push_back(std::move(r));
    };
    row("target position P_i (" + tu + ")", [&](std::size_t i) { return fmt::format("{:g}", T[i].target); });
    if (has_up)
      for (std::size_t j = 0; j < runs_up; ++j)
        row(fmt::format("x_i{}↑ (run {} ↑)", j + 1, j + 1), [&](std::size_t i) { return deviation(runs.up, i, j); });
    if (has_down)
      for (std::size_t j = 0; j < runs_down; ++j)
        row(fmt::format("x_i{}↓ (run {} ↓)", j + 1, j + 1), [&](std::size_t i) { return deviation(runs.down, i, j); });
    if (has_up) row("x̄_i↑ mean deviation ↑", [&](std::size_t i) { return f(T[i].mean_up); });
    if (has_down) row("x̄_i↓ mean deviation ↓", [&](std::size_t i) { return f(T[i].mean_down); });
    if (has_up) row("s_i↑ standard uncertainty ↑", [&](std::size_t i) { return f(T[i].s_up); });
    if (has_down) row("s_i↓ standard uncertainty ↓", [&](std::size_t i) { return f(T[i].s_down); });
    if (has_up) row("2s_i↑", [&](std::size_t i) { return f(2 * T[i].s_up); });
    if (has_down) row("2s_i↓", [&](std::size_t i) { return f(2 * T[i].s_down); });
    if (has_up) {
      row("x̄_i↑ + 2s_i↑", [&](std::size_t i) { return f(T[i].mean_up + 2 * T[i].s_up); });
      row("x̄_i↑ − 2s_i↑", [&](std::size_t i) { return f(T[i].mean_up - 2 * T[i].s_up); });
    }
    if (has_down) {
      row("x̄_i↓ + 2s_i↓", [&](std::size_t i) { return f(T[i].mean_down + 2 * T[i].s_down); });
      row("x̄_i↓ − 2s_i↓", [&](std::size_t i) { return f(T[i].mean_down - 2 * T[i].s_down); });
    }
    if (has_up) row("R_i↑ = 4s_i↑ repeatability ↑", [&](std::size_t i) { return f(T[i].R_up); });
    if (has_down) row("R_i↓ = 4s_i↓ repeatability ↓", [&](std::size_t i) { return f(T[i].R_down); });
    if (has_up && has_down) {
      row("B_i = x̄_i↑ − x̄_i↓ reversal", [&](std::size_t i) { return f(T[i].reversal); });
      row("R_i bidirectional repeatability", [&](std::size_t i) { return f(T[i].R); });
      row("x̄_i = (x̄_i↑ + x̄_i↓)/2", [&](std::size_t i) { return f(T[i].mean); });
    }
    blocks.push_back(std::move(b));
  }
  return blocks;
}

Report positioning_report(const std::string& command, const PositioningRuns& runs, const std::string& runs_sha256,
                          const PositioningEvaluation& e, const ToleranceVerdict& verdict, const ReportMetadata& metadata) {
  const auto target_unit = find_unit(e.target_unit.empty() ? e.unit : e.target_unit);
  const bool rotary = target_unit && target_unit->dimension == Dimension::Angle;
  Report r(rotary ? "ISO 230-2 positioning of a rotary axis" : "ISO 230-2 positioning of a linear axis", command);
  r.set_metadata(metadata);
  r.add_input("measurements", runs.source, runs_sha256);
  r.set_verdict(verdict);
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
  if (e.runs < 5)
    r.add_warning(
        fmt::format("ISO 230-2:2014 clause 4.3 asks for 5 runs in each direction at each target; this "
                    "test has {}: the standard deviations, and A and R with them, are less certain.",
                    e.runs));
  for (const auto& w : missing_acceptance_fields(r.metadata(), AcceptanceTest::Iso230_2))
    r.add_warning("Test conditions: " + w + ".");

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
  auto trace = [&](const char* mode, const json& xs, const json& ys, const char* name, json style) {
    json t = {{"type", "scatter"}, {"mode", mode}, {"x", xs}, {"y", ys}, {"name", name}};
    t[std::string(mode) == "markers" ? "marker" : "line"] = std::move(style);
    data.push_back(std::move(t));
  };
  trace("lines+markers", x, up, "x̄↑ (up)", {{"color", "rgb(31,119,180)"}});
  trace("lines+markers", x, dn, "x̄↓ (down)", {{"color", "rgb(214,39,40)"}});
  trace("lines", x, mean, "x̄ (bidirectional)", {{"color", "black"}, {"dash", "dot"}});
  trace("markers", rx_up, ry_up, "runs up", {{"size", 4}, {"color", "rgb(31,119,180)"}});
  trace("markers", rx_dn, ry_dn, "runs down", {{"size", 4}, {"color", "rgb(214,39,40)"}});
  // A, E, M, R and B marked as brackets (ISO 230-2:2014 figures), for a bidirectional test.
  json layout = {{"xaxis", {{"title", {{"text", "target (" + tu + ")"}}}}},
                 {"yaxis", {{"title", {{"text", "deviation (" + u + ")"}}}}},
                 {"legend", {{"orientation", "h"}, {"y", -0.2}}}};
  if (both && !e.targets.empty()) {
    double lo_a = 1e300, hi_a = -1e300, lo_e = 1e300, hi_e = -1e300, lo_m = 1e300, hi_m = -1e300;
    std::size_t i_r = 0, i_b = 0;
    for (std::size_t i = 0; i < e.targets.size(); ++i) {
      const auto& t = e.targets[i];
      lo_a = std::min({lo_a, t.mean_up - 2 * t.s_up, t.mean_down - 2 * t.s_down});
      hi_a = std::max({hi_a, t.mean_up + 2 * t.s_up, t.mean_down + 2 * t.s_down});
      lo_e = std::min({lo_e, t.mean_up, t.mean_down});
      hi_e = std::max({hi_e, t.mean_up, t.mean_down});
      lo_m = std::min(lo_m, t.mean);
      hi_m = std::max(hi_m, t.mean);
      if (t.R > e.targets[i_r].R) i_r = i;
      if (std::abs(t.reversal) > std::abs(e.targets[i_b].reversal)) i_b = i;
    }
    // Brackets: a vertical segment with end ticks and a label, in data coordinates. The labels
    // are placed so that no two can overlap at any plot width: a label above its bracket
    // (Label::Above) has its bottom at the bracket's top, one below has its top at the bracket's
    // bottom; sideways it is centred on the bracket or lies wholly to its left or right.
    const double x0 = e.targets.front().target, x1 = e.targets.back().target;
    const double span = std::abs(x1 - x0) > 0 ? std::abs(x1 - x0) : 1.0;
    json shapes = json::array(), notes = json::array();
    enum class Side { Centre, Left, Right };
    auto bracket = [&](double xb, double lo, double hi, const std::string& label, const char* colour, bool above,
                       Side side) {
      const double tick = span * 0.008;
      for (auto [xa, ya, xc, yc] :
           {std::array{xb, lo * k, xb, hi * k}, std::array{xb - tick, lo * k, xb + tick, lo * k},
            std::array{xb - tick, hi * k, xb + tick, hi * k}})
        shapes.push_back({{"type", "line"},
                          {"x0", xa},
                          {"y0", ya},
                          {"x1", xc},
                          {"y1", yc},
                          {"line", {{"color", colour}, {"width", 2}}}});
      notes.push_back({{"x", xb},
                       {"y", (above ? hi : lo) * k},
                       {"text", label},
                       {"showarrow", false},
                       {"xanchor", side == Side::Centre ? "center" : side == Side::Left ? "right" : "left"},
                       {"xshift", side == Side::Centre ? 0 : side == Side::Left ? -3 : 3},
                       {"yanchor", above ? "bottom" : "top"},
                       // Readable where a label lies on the data.
                       {"bgcolor", "rgba(255,255,255,0.75)"},
                       {"font", {{"color", colour}, {"size", 13}}}});
    };
    // The whole-axis brackets right of the data. Their tops and bottoms are ordered (M's range
    // lies within E's, E's within A's): E above, M below, A above and to its right, so that E
    // and A never meet.
    const double right = std::max(x0, x1);
    bracket(right + 0.06 * span, lo_e, hi_e, fmt::format("E {:.2f}", e.E * k), "rgb(44,160,44)", true, Side::Centre);
    bracket(right + 0.12 * span, lo_m, hi_m, fmt::format("M {:.2f}", e.M * k), "rgb(0,0,0)", false, Side::Centre);
    bracket(right + 0.18 * span, lo_a, hi_a, fmt::format("A {:.2f}", e.A * k), "rgb(148,103,189)", true, Side::Right);
    {
      const auto& t = e.targets[i_r];
      double lo = std::min(t.mean_up - 2 * t.s_up, t.mean_down - 2 * t.s_down);
      double hi = std::max(t.mean_up + 2 * t.s_up, t.mean_down + 2 * t.s_down);
      if (t.R == t.R_up && t.R_up > 2 * t.s_up + 2 * t.s_down + std::abs(t.reversal))
        lo = t.mean_up - 2 * t.s_up, hi = t.mean_up + 2 * t.s_up;
      else if (t.R == t.R_down && t.R_down > 2 * t.s_up + 2 * t.s_down + std::abs(t.reversal))
        lo = t.mean_down - 2 * t.s_down, hi = t.mean_down + 2 * t.s_down;
      // R's label above its bracket, B's below; of the two, the label of the bracket further
      // left lies to its left and the other's to its right (at one target: B left, R right).
      // R's bracket holds both means of its target, so at one target R's top is above B's bottom.
      const auto& b = e.targets[i_b];
      const double xr = t.target + 0.012 * span, xb = b.target - 0.012 * span;
      bracket(xr, lo, hi, fmt::format("R {:.2f}", e.R * k), "rgb(255,127,14)", true,
              xr > xb ? Side::Right : Side::Left);
      bracket(xb, std::min(b.mean_up, b.mean_down), std::max(b.mean_up, b.mean_down), fmt::format("B {:.2f}", e.B * k),
              "rgb(140,86,75)", false, xr > xb ? Side::Left : Side::Right);
    }
    layout["xaxis"]["range"] = {std::min(x0, x1) - 0.03 * span, right + 0.30 * span};
    layout["shapes"] = shapes;
    layout["annotations"] = notes;
  }
  r.add_plot("Positional deviation x = measured − target (" + u + ") against the target position (" + tu +
                 "); A, E, M, R, B marked",
             {{"data", data}, {"layout", layout}});

  r.add_section("Per target (ISO 230-2:2014 table layout)");
  r.add_paragraph(
      "One column per target position P_i, as ISO 230-2:2014 lays out its results: the deviations x_ij = "
      "measured − target of every run j, then per approach direction (↑ positive, ↓ negative) the mean "
      "deviation x̄_i, the standard uncertainty s_i (n − 1), the 2s_i bands, the repeatability R_i = 4 s_i; "
      "then the reversal value B_i = x̄_i↑ − x̄_i↓, the bidirectional repeatability R_i = max(2 s_i↑ + 2 s_i↓ "
      "+ |B_i|, R_i↑, R_i↓) and the mean bidirectional deviation x̄_i = (x̄_i↑ + x̄_i↓)/2. Values in " +
      u + "; n/a where the test does not define the value (one run: no s).");
  for (const auto& block : positioning_target_table(runs, e, shown))
    r.add_table(block.caption, block.columns, block.rows);
  {
    // M, B and B̄ are bidirectional only (ISO 230-2:2014 clause 2): "-" in the direction columns.
    auto row = [&](const char* name, double bi, std::optional<double> up_v, std::optional<double> down_v) {
      return std::vector<std::string>{name, both ? shown.format(bi) : "-", has_up && up_v ? shown.format(*up_v) : "-",
                                      has_down && down_v ? shown.format(*down_v) : "-"};
    };
    r.add_table("Axis results (" + u + "), ISO 230-2:2014 clause 2: bidirectional and per approach direction",
                {"quantity", "bidirectional", "unidirectional ↑", "unidirectional ↓"},
                {row("accuracy A", e.A, e.A_up, e.A_down), row("systematic positioning error E", e.E, e.E_up, e.E_down),
                 row("mean positioning error M", e.M, {}, {}), row("repeatability R", e.R, e.R_up, e.R_down),
                 row("reversal value B", e.B, {}, {}), row("mean reversal value B̄", e.B_mean, {}, {})});
  }
  if (!runs.metadata.empty()) {
    std::vector<std::vector<std::string>> meta;
    for (const auto& [key, value] : runs.metadata) meta.push_back({key, value});
    r.add_table("What the file says beside the runs", {"key", "value"}, meta);
  }
  return r;
}

void write_positioning_report(const std::string& path, const std::string& command, const PositioningRuns& runs,
                              const PositioningEvaluation& e, const ToleranceVerdict& verdict) {
  positioning_report(command, runs, sha256_hex(read_text_file(runs.source, "measurements")), e, verdict,
                     session_metadata())
      .write(path);
}

Report ballbar_report(const std::string& command, const BallbarTrace& trace, const std::string& trace_sha256,
                      const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                      const std::string& plane, double radius, double feed, const ToleranceVerdict& verdict,
                      const ReportMetadata& metadata) {
  const std::vector<TracePoint>& t = trace.points;
  Report r("ISO 230-4 circular test, plane " + plane, command);
  r.set_metadata(metadata);
  r.add_input("trace", trace.source, trace_sha256);
  r.set_verdict(verdict);
  const ReportMetadata& meta = r.metadata();
  for (const auto& w : missing_acceptance_fields(meta, AcceptanceTest::Iso230_4))
    if (!(feed > 0 && w.find("(feed)") != std::string::npos)) r.add_warning("Recording conditions: " + w + ".");
  r.add_figure("nominal radius", fmt::format("{:g}", radius), "mm");
  if (feed > 0) r.add_figure("feed", fmt::format("{:g}", feed), "mm/min");
  if (e.cw) r.add_figure("G (CW)", fmt::format("{:.2f}", e.cw->G * 1e3), "µm");
  if (e.ccw) r.add_figure("G (CCW)", fmt::format("{:.2f}", e.ccw->G * 1e3), "µm");
  if (e.G_b) r.add_figure("G(b)", fmt::format("{:.2f}", *e.G_b * 1e3), "µm");
  if (e.H) r.add_figure("H", fmt::format("{:.2f}", *e.H * 1e3), "µm");
  r.add_figure("F max / min", fmt::format("{:.2f} / {:.2f}", e.F_max * 1e3, e.F_min * 1e3), "µm");
  {
    // ISO 230-4:2005 clause 6: the conditions a circular test's result is only valid with.
    auto given = [&](std::string_view key) {
      const std::string* v = meta.get(key);
      return v ? *v : std::string("not stated");
    };
    bool cw = false, ccw = false;
    for (const auto& s : t) (s.direction == CircleDirection::CW ? cw : ccw) = true;
    std::string temperature = "not stated";
    for (std::string_view key : {"temperature", "temperature_air", "temperature_machine", "temperature_material"})
      if (const std::string* v = meta.get(key))
        temperature = (temperature == "not stated" ? std::string() : temperature + "; ") +
                      std::string(metadata_label(key)) + " " + *v;
    r.add_section("Recording conditions (ISO 230-4:2005 clause 6)");
    r.add_table("Conditions of the test", {"condition", "value"},
                {{"plane", plane},
                 {"nominal radius", fmt::format("{:g} mm", radius)},
                 {"feed", feed > 0 ? fmt::format("{:g} mm/min", feed) : given("feed")},
                 {"direction of the contouring", cw && ccw ? "clockwise and counter-clockwise"
                                                 : cw      ? "clockwise"
                                                           : "counter-clockwise"},
                 {"start position", given("start")},
                 {"data capture", given("data_capture")},
                 {"compensation", given("compensation")},
                 {"position of the centre", given("centre")},
                 {"temperature", temperature},
                 {"instrument", given("instrument")}});
  }
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
  return r;
}

void write_ballbar_report(const std::string& path, const std::string& command, const BallbarTrace& trace,
                          const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                          const std::string& plane, double radius, double feed, const ToleranceVerdict& verdict) {
  ballbar_report(command, trace, sha256_hex(read_text_file(trace.source, "trace")), e, diagnosis, plane, radius, feed,
                 verdict, session_metadata())
      .write(path);
}

Report comparison_report(const std::string& command, const MethodComparison& c, const std::string& data_sha256,
                         const ReportMetadata& metadata) {
  const auto& s = c.summary;
  Report r(fmt::format("Method comparison: {} and {}", c.methods[0], c.methods[1]), command);
  r.set_metadata(metadata);
  r.add_input("data", c.source, data_sha256);
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
  return r;
}

void write_comparison_report(const std::string& path, const std::string& command, const MethodComparison& c) {
  comparison_report(command, c, sha256_hex(read_text_file(c.source, "data")), session_metadata())
      .write(path);
}

}  // namespace mtcal
