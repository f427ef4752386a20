// HTML trend report of one machine's calibration history.
#include "mtcal/report/history.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

namespace {

using nlohmann::json;

// Plotly reads "yyyy-mm-dd HH:MM:SS" as a date (local to the plot, no zone): times are UTC.
std::string plot_time(HistoryTime t) {
  std::string s = format_history_time(t);
  s[10] = ' ';
  s.pop_back();
  return s;
}

std::string num(double v) { return fmt::format("{:.4g}", v); }

std::string band_text(const std::optional<ToleranceBand>& b, const std::string& unit) {
  if (!b) return "–";
  if (b->one_sided()) return fmt::format("≤ {} {}", num(b->hi), unit);
  if (b->lo == -b->hi) return fmt::format("|value| ≤ {} {}", num(b->hi), unit);
  return fmt::format("[{}, {}] {}", num(b->lo), num(b->hi), unit);
}

const char* event_colour(EventKind k) {
  switch (k) {
    case EventKind::CompensationLoaded: return "#2ca02c";
    case EventKind::Crash: return "#d62728";
    case EventKind::Repair: return "#ff7f0e";
    case EventKind::Other: return "#7f7f7f";
  }
  return "#7f7f7f";
}

std::string crossing_text(const TrendResult& t) {
  const LimitCrossing& c = t.crossing;
  switch (c.status) {
    case CrossingStatus::NoTolerance: return "no tolerance given";
    case CrossingStatus::NoFit: return "no line (see note)";
    case CrossingStatus::AlreadyOutside: return "already outside (latest calibration)";
    case CrossingStatus::NotTowardsLimit: return "not drifting towards a limit";
    case CrossingStatus::Predicted: break;
  }
  if (!c.date) return "beyond 10,000 years";
  std::string s = format_history_date(*c.date);
  if (c.years_from_last && *c.years_from_last < 0) s += " (the fitted line is already past the limit)";
  if (c.earliest)
    s += fmt::format(" (between {} and {})", format_history_date(*c.earliest),
                     c.latest ? format_history_date(*c.latest) : std::string("possibly never"));
  return s;
}

std::string rate_text(const QuantityTrend& q) {
  const TrendResult& t = q.trend;
  if (t.kind == TrendFitKind::None) return "–";
  return t.u_rate ? fmt::format("{} ± {} {}/year", num(t.rate_per_year), num(*t.u_rate), q.unit)
                  : fmt::format("{} {}/year (no uncertainty)", num(t.rate_per_year), q.unit);
}

json series_plot(const QuantityTrend& q, const std::vector<Event>& events, std::vector<HistoryTime> event_times) {
  const TrendResult& t = q.trend;
  json data = json::array();
  json x = json::array(), y = json::array(), hi = json::array(), lo = json::array(), hover = json::array();
  bool any_u = false;
  for (const auto& s : q.samples) {
    x.push_back(plot_time(s.at));
    y.push_back(s.value);
    const double u2 = s.u ? 2.0 * *s.u : 0.0;
    any_u = any_u || s.u.has_value();
    hi.push_back(s.value + u2);
    lo.push_back(s.value - u2);
    hover.push_back(fmt::format("record {}<br>{} {}{}", s.record, num(s.value), q.unit,
                                s.u ? fmt::format(" (u = {})", num(*s.u)) : std::string(" (no u)")));
  }
  if (any_u) {
    data.push_back({{"type", "scatter"},
                    {"mode", "lines"},
                    {"x", x},
                    {"y", hi},
                    {"line", {{"width", 0}}},
                    {"hoverinfo", "skip"},
                    {"showlegend", false}});
    data.push_back({{"type", "scatter"},
                    {"mode", "lines"},
                    {"x", x},
                    {"y", lo},
                    {"line", {{"width", 0}}},
                    {"fill", "tonexty"},
                    {"fillcolor", "rgba(31,119,180,0.2)"},
                    {"hoverinfo", "skip"},
                    {"name", "±2u (k = 2)"}});
  }
  data.push_back({{"type", "scatter"},
                  {"mode", "lines+markers"},
                  {"x", x},
                  {"y", y},
                  {"name", "calibrations"},
                  {"line", {{"color", "#1f77b4"}}},
                  {"marker", {{"size", 7}}},
                  {"hovertext", hover},
                  {"hoverinfo", "x+text"}});

  // The time span drawn: the samples, the events, and the predicted crossing when it is near.
  HistoryTime start = t.first, end = t.last;
  for (const auto& e : event_times) start = std::min(start, e), end = std::max(end, e);
  const double span_years = std::max(1.0, static_cast<double>((t.last - t.first).count()) / kSecondsPerYear);
  const auto after_last = [&](double years) {
    return t.last + std::chrono::seconds(static_cast<std::int64_t>(std::llround(years * kSecondsPerYear)));
  };
  const LimitCrossing& c = t.crossing;
  const bool show_crossing = c.status == CrossingStatus::Predicted && c.date && c.years_from_last &&
                             *c.years_from_last <= std::max(3.0 * span_years, 5.0);
  if (show_crossing) {
    end = std::max(end, *c.date);
    // The whole interval when its late end is near too: the slow line is seen reaching the limit.
    if (c.latest && *c.latest <= after_last(std::max(3.0 * span_years, 5.0))) end = std::max(end, *c.latest);
  }
  if (t.kind != TrendFitKind::None) end = std::max(end, after_last(0.1 * span_years));
  const HistoryTime fit_end = end;

  if (t.kind != TrendFitKind::None) {
    data.push_back({{"type", "scatter"},
                    {"mode", "lines"},
                    {"x", {plot_time(t.first), plot_time(fit_end)}},
                    {"y", {t.at(t.first), t.at(fit_end)}},
                    {"line", {{"color", "#ff7f0e"}, {"width", 2}}},
                    {"name", "drift " + rate_text(q)}});
    if (t.u_rate && *t.u_rate > 0) {
      // rate ± 2u(rate) turning about (t_ref, level): the lines that give the crossing interval.
      for (const double sign : {1.0, -1.0}) {
        const double r = t.rate_per_year + sign * 2.0 * *t.u_rate;
        auto at = [&](HistoryTime when) {
          return t.level + r * static_cast<double>((when - t.t_ref).count()) / kSecondsPerYear;
        };
        data.push_back({{"type", "scatter"},
                        {"mode", "lines"},
                        {"x", {plot_time(t.first), plot_time(fit_end)}},
                        {"y", {at(t.first), at(fit_end)}},
                        {"line", {{"color", "#ff7f0e"}, {"width", 1}, {"dash", "dot"}}},
                        {"name", "rate ± 2u(rate)"},
                        {"showlegend", sign > 0},
                        {"legendgroup", "fan"}});
      }
    }
  }
  json shapes = json::array(), annotations = json::array();
  if (t.band) {
    for (const double limit : {t.band->lo, t.band->hi}) {
      if (!std::isfinite(limit)) continue;
      data.push_back({{"type", "scatter"},
                      {"mode", "lines"},
                      {"x", {plot_time(start), plot_time(end)}},
                      {"y", {limit, limit}},
                      {"line", {{"color", "#d62728"}, {"dash", "dash"}, {"width", 1.5}}},
                      {"name", "tolerance " + band_text(t.band, q.unit)},
                      {"legendgroup", "tolerance"},
                      {"showlegend", limit == t.band->hi}});
    }
  }
  if (show_crossing) {
    data.push_back({{"type", "scatter"},
                    {"mode", "markers"},
                    {"x", {plot_time(*c.date)}},
                    {"y", {*c.limit}},
                    {"marker", {{"symbol", "x"}, {"size", 13}, {"color", "#d62728"}}},
                    {"name", "predicted crossing " + format_history_date(*c.date)}});
    if (c.earliest) {
      const HistoryTime a = std::max(*c.earliest, start), b = c.latest ? std::min(*c.latest, end) : end;
      if (a < b)
        shapes.push_back({{"type", "rect"},
                          {"xref", "x"},
                          {"yref", "paper"},
                          {"x0", plot_time(a)},
                          {"x1", plot_time(b)},
                          {"y0", 0},
                          {"y1", 1},
                          {"fillcolor", "rgba(214,39,40,0.08)"},
                          {"line", {{"width", 0}}},
                          {"layer", "below"}});
    }
  }
  for (std::size_t i = 0; i < events.size(); ++i) {
    const std::string when = plot_time(event_times[i]);
    shapes.push_back({{"type", "line"},
                      {"xref", "x"},
                      {"yref", "paper"},
                      {"x0", when},
                      {"x1", when},
                      {"y0", 0},
                      {"y1", 1},
                      {"line", {{"color", event_colour(events[i].kind)}, {"width", 1.5}, {"dash", "dot"}}}});
    annotations.push_back({{"x", when},
                           {"xref", "x"},
                           {"y", 1},
                           {"yref", "paper"},
                           {"yanchor", "bottom"},
                           {"text", std::string(to_string(events[i].kind))},
                           {"showarrow", false},
                           {"font", {{"size", 10}, {"color", event_colour(events[i].kind)}}},
                           {"hovertext", events[i].date + ": " + events[i].note}});
  }
  json layout = {{"xaxis", {{"type", "date"}, {"title", {{"text", "measured at (UTC)"}}}}},
                 {"yaxis", {{"title", {{"text", q.quantity + " (" + q.unit + ")"}}}}},
                 {"legend", {{"orientation", "h"}, {"y", -0.22}}},
                 {"margin", {{"l", 70}, {"r", 20}, {"t", 40}, {"b", 40}}},
                 {"shapes", shapes},
                 {"annotations", annotations}};
  return {{"data", data}, {"layout", layout}};
}

}  // namespace

namespace {

Report trend_report(const std::string& command, const MachineTrends& m, const std::vector<CalibrationRecord>& records,
                    const std::string& store) {
  Report r("Calibration history: " + m.machine, command);
  r.set_metadata({});  // the calibrations' metadata is a table of its own below
  r.set_machine_label(m.serial.empty() ? m.machine : m.machine + " (serial " + m.serial + ")");
  r.add_figure("store", store, "");
  r.add_figure("calibrations", fmt::format("{}", records.size()),
               records.empty() ? std::string()
                               : fmt::format("from {} to {}", records.front().measured_at, records.back().measured_at));
  r.add_figure("events", fmt::format("{}", m.events.size()), "");
  for (const auto& q : m.series) {
    if (q.trend.kind != TrendFitKind::None) r.add_figure(q.quantity + " drift", rate_text(q), "");
    if (q.trend.band) r.add_figure(q.quantity + " leaves its tolerance", crossing_text(q.trend), "");
  }
  for (const auto& q : m.series) {
    if (!q.trend.note.empty()) r.add_warning(q.quantity + ": " + q.trend.note + ".");
    if (q.trend.crossing.status == CrossingStatus::AlreadyOutside)
      r.add_warning(fmt::format("{} is outside its tolerance ({}) at the latest calibration: {} {}.", q.quantity,
                                band_text(q.trend.band, q.unit), num(q.trend.last_value), q.unit));
  }

  std::vector<HistoryTime> event_times;
  for (const auto& e : m.events) event_times.push_back(parse_history_time(e.date, "event " + e.id, "date"));

  r.add_section("Trends");
  r.add_paragraph(
      "Each line is a least-squares straight line through the calibrations: weighted by 1/u² when every "
      "calibration states its standard uncertainty u, else ordinary with the uncertainty from the scatter. The band "
      "is ±2u of each calibration (k = 2). The dotted lines turn the fitted line about the calibrations' mean time "
      "with the rate ± 2u(rate): where they reach the tolerance is the interval of the predicted date "
      "(docs/history.md).");
  std::vector<std::vector<std::string>> rows;
  for (const auto& q : m.series) {
    const TrendResult& t = q.trend;
    rows.push_back({q.quantity, q.figure ? "figure" : "parameter", fmt::format("{}", t.n), to_string(t.kind),
                    rate_text(q),
                    t.n ? fmt::format("{} {} ({})", num(t.last_value), q.unit, format_history_date(t.last)) : "–",
                    band_text(t.band, q.unit), t.utilisation ? fmt::format("{:.0f} %", 100 * *t.utilisation) : "–",
                    crossing_text(t)});
  }
  r.add_table("Trend per quantity",
              {"quantity", "kind", "calibrations", "fit", "drift rate ± u", "latest", "tolerance", "tolerance used",
               "leaves the tolerance"},
              rows);
  for (const auto& q : m.series) {
    if (q.samples.empty()) continue;
    r.add_section(q.quantity);
    r.add_plot(fmt::format("{} of {} over time ({}); events as vertical lines (hover for the note)", q.quantity,
                           m.machine, q.unit),
               series_plot(q, m.events, event_times));
  }

  r.add_section("Events");
  if (m.events.empty()) {
    r.add_paragraph("No events recorded (mtcal history event add).");
  } else {
    rows.clear();
    for (const auto& e : m.events) rows.push_back({e.date, std::string(to_string(e.kind)), e.note});
    r.add_table("Events of the machine", {"date", "kind", "note"}, rows);
  }

  r.add_section("Calibrations");
  std::set<std::string> keys;
  for (const auto& rec : records)
    for (const auto& [k, v] : rec.metadata) keys.insert(k);
  std::vector<std::string> columns{"record", "measured at", "command"};
  std::vector<std::string> ordered;
  for (const auto& f : metadata_fields())
    if (keys.count(std::string(f.key))) ordered.emplace_back(f.key);
  for (const auto& k : keys)
    if (std::find(ordered.begin(), ordered.end(), k) == ordered.end()) ordered.push_back(k);
  for (const auto& k : ordered) columns.emplace_back(metadata_label(k));
  rows.clear();
  for (const auto& rec : records) {
    std::vector<std::string> row{rec.id, rec.measured_at, rec.command};
    for (const auto& k : ordered) {
      const auto it = rec.metadata.find(k);
      row.push_back(it == rec.metadata.end() ? "" : it->second);
    }
    rows.push_back(std::move(row));
  }
  r.add_table("Calibrations of the machine and their metadata", columns, rows);
  return r;
}

}  // namespace

void write_trend_report(const std::string& path, const std::string& command, const MachineTrends& m,
                        const std::vector<CalibrationRecord>& records, const std::string& store) {
  trend_report(command, m, records, store).write(path);
}

std::string trend_report_html(const std::string& command, const MachineTrends& m,
                              const std::vector<CalibrationRecord>& records, const std::string& store,
                              const std::string& date) {
  return trend_report(command, m, records, store).html(date);
}

}  // namespace mtcal
