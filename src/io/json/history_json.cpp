// JSON of the history analyses: record summaries, diff, trend, fleet ranking.
#include "mtcal/io/json/history_json.hpp"

#include <algorithm>
#include <cmath>

namespace mtcal {

namespace {

Json or_null(const std::optional<double>& v) { return number_or_null(v); }
Json date_or_null(const std::optional<HistoryTime>& t) { return t ? Json(format_history_time(*t)) : Json(nullptr); }

Json band_json(const std::optional<ToleranceBand>& b) {
  if (!b) return nullptr;
  return {{"lo", number_or_null(b->lo)}, {"hi", number_or_null(b->hi)}};
}

Json crossing_json(const LimitCrossing& c) {
  return {{"status", to_string(c.status)},
          {"limit", or_null(c.limit)},
          {"date", date_or_null(c.date)},
          {"years_from_last", or_null(c.years_from_last)},
          {"earliest", date_or_null(c.earliest)},
          {"latest", date_or_null(c.latest)}};
}

}  // namespace

Json to_json(const CalibrationDiff& d) {
  Json changes = Json::array();
  for (const auto& c : d.changes)
    changes.push_back({{"name", c.name},
                       {"unit", c.unit},
                       {"before", or_null(c.before)},
                       {"u_before", or_null(c.u_before)},
                       {"after", or_null(c.after)},
                       {"u_after", or_null(c.u_after)},
                       {"delta", or_null(c.delta)},
                       {"u_delta", or_null(c.u_delta)},
                       {"en", or_null(c.en)},
                       {"verdict", to_string(c.verdict)},
                       {"reason", c.reason.empty() ? Json(nullptr) : Json(c.reason)}});
  return {{"summary",
           {{"significant", d.significant},
            {"not_significant", d.not_significant},
            {"not_assessable", d.not_assessable},
            {"added", d.added},
            {"removed", d.removed}}},
          {"changes", changes}};
}

Json to_json(const RecordDiff& d) {
  return {{"first", d.first},
          {"second", d.second},
          {"coverage_factor", d.parameters.options.coverage_factor},
          {"en_limit", d.parameters.options.en_limit},
          {"parameters", to_json(d.parameters)},
          {"figures", to_json(d.figures)}};
}

Json to_json(const TrendResult& t) {
  const bool fitted = t.kind != TrendFitKind::None;
  return {{"n", t.n},
          {"fit", to_string(t.kind)},
          {"t_ref", fitted ? Json(format_history_time(t.t_ref)) : Json(nullptr)},
          {"level", fitted ? number_or_null(t.level) : Json(nullptr)},
          {"u_level", or_null(t.u_level)},
          {"rate_per_year", fitted ? number_or_null(t.rate_per_year) : Json(nullptr)},
          {"u_rate_per_year", or_null(t.u_rate)},
          {"residual_sd", or_null(t.residual_sd)},
          {"birge_ratio", or_null(t.birge_ratio)},
          {"inflated", t.inflated},
          {"first", t.n ? Json(format_history_time(t.first)) : Json(nullptr)},
          {"last", t.n ? Json(format_history_time(t.last)) : Json(nullptr)},
          {"last_value", t.n ? number_or_null(t.last_value) : Json(nullptr)},
          {"tolerance", band_json(t.band)},
          {"utilisation", or_null(t.utilisation)},
          {"crossing", crossing_json(t.crossing)},
          {"note", t.note.empty() ? Json(nullptr) : Json(t.note)}};
}

Json to_json(const QuantityTrend& q) {
  Json samples = Json::array();
  for (const auto& s : q.samples)
    samples.push_back(
        {{"record", s.record}, {"measured_at", format_history_time(s.at)}, {"value", s.value}, {"u", or_null(s.u)}});
  return {{"quantity", q.quantity},
          {"kind", q.figure ? "figure" : "parameter"},
          {"unit", q.unit},
          {"samples", samples},
          {"trend", to_json(q.trend)}};
}

Json to_json(const MachineTrends& m) {
  Json series = Json::array(), events = Json::array();
  for (const auto& q : m.series) series.push_back(to_json(q));
  for (const auto& e : m.events)
    events.push_back({{"id", e.id}, {"date", e.date}, {"kind", std::string(to_string(e.kind))}, {"note", e.note}});
  return {{"machine", m.machine},
          {"serial", m.serial.empty() ? Json(nullptr) : Json(m.serial)},
          {"series", series},
          {"events", events}};
}

Json to_json(const RankedMachine& m) {
  Json qs = Json::array();
  for (const auto& q : m.quantities) {
    const TrendResult& t = q.trend;
    qs.push_back({{"quantity", q.quantity},
                  {"unit", q.unit},
                  {"latest", number_or_null(t.last_value)},
                  {"latest_at", format_history_time(t.last)},
                  {"tolerance", band_json(t.band)},
                  {"utilisation", or_null(t.utilisation)},
                  {"n", t.n},
                  {"rate_per_year", t.kind != TrendFitKind::None ? number_or_null(t.rate_per_year) : Json(nullptr)},
                  {"u_rate_per_year", or_null(t.u_rate)},
                  {"crossing", crossing_json(t.crossing)}});
  }
  return {{"rank", m.rank},
          {"machine", m.machine},
          {"utilisation", number_or_null(m.utilisation)},
          {"years_to_limit", or_null(m.years_to_limit)},
          {"outside", m.outside},
          {"quantities", qs}};
}

Json to_json(const FleetRanking& r) {
  Json machines = Json::array();
  for (const auto& m : r.machines) machines.push_back(to_json(m));
  return {{"order", r.options.order == RankOrder::Utilisation ? "utilisation" : "time_to_limit"},
          {"machines", machines}};
}

Json record_summary_json(const CalibrationRecord& r) {
  Json j;
  j["id"] = r.id;
  j["machine"] = r.machine_name;
  j["serial"] = r.machine_serial;
  j["command"] = r.command;
  j["measured_at"] = r.measured_at;
  j["recorded_at"] = r.recorded_at;
  j["parameters"] = r.parameters.size();
  Json figs = Json::object();
  for (const auto& f : r.figures) figs[f.name] = {{"value", f.value}, {"unit", f.unit}};
  j["figures"] = figs;
  j["content_hash"] = r.content_hash;
  return j;
}

}  // namespace mtcal
