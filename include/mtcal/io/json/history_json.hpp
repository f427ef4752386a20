// JSON of the history: record summaries (the list view), diff, trend, fleet ranking.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "mtcal/history/analysis.hpp"
#include "mtcal/history/record.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// A record in a list of records (history list --json): {"id", "machine", "serial", "command",
// "measured_at", "recorded_at", "parameters" (their count), "figures": {name: {value, unit}}, "content_hash"}.
Json record_summary_json(const CalibrationRecord& r);

// Keys are documented in docs/history.md ("JSON"); absent values are null, dates ISO 8601 UTC.
// {"first", "second", "coverage_factor", "en_limit", "parameters": {...}, "figures": {...}} with
// each part {"summary": {significant, not_significant, not_assessable, added, removed},
// "changes": [{name, unit, before, u_before, after, u_after, delta, u_delta, en, verdict, reason}]}.
Json to_json(const RecordDiff& d);
Json to_json(const CalibrationDiff& d);
// {"n", "fit", "t_ref", "level", "u_level", "rate_per_year", "u_rate_per_year", "residual_sd",
// "birge_ratio", "inflated", "first", "last", "last_value", "tolerance": {lo, hi} | null,
// "utilisation", "crossing": {status, limit, date, years_from_last, earliest, latest}, "note"}.
Json to_json(const TrendResult& t);
// {"quantity", "kind": "parameter"|"figure", "unit", "samples": [{record, measured_at, value, u}], "trend"}.
Json to_json(const QuantityTrend& q);
// {"machine", "serial", "series": [...], "events": [{id, date, kind, note}]}.
Json to_json(const MachineTrends& m);
// {"order", "machines": [{rank, machine, utilisation, years_to_limit, outside, quantities: [{quantity,
// unit, latest, latest_at, tolerance, utilisation, rate_per_year, u_rate_per_year, crossing}]}]}.
Json to_json(const FleetRanking& r);
// One machine's entry of to_json(FleetRanking)'s "machines" (mtcal serve keeps each machine's
// entry and makes again only those of machines whose ranking changed).
Json to_json(const RankedMachine& m);

}  // namespace mtcal
