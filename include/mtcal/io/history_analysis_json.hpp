// JSON of the history analyses (diff, trend, fleet ranking) and acceptance tolerances as history bands.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "mtcal/history/analysis.hpp"
#include "mtcal/io/acceptance_files.hpp"
#include "mtcal/io/json.hpp"

namespace mtcal {

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

// The limits of a tolerance file (docs/reports.md) as bands of the figures record_from_result
// names (docs/history.md): ISO 230-2 quantity Q of axis X limits figure "Q_X" (the section "any"
// every axis in `axes` the file does not list, and "Q" recorded without an axis), value <= limit;
// ISO 230-4 G limits G_b, G_cw, G_ccw, F limits |F_max| and |F_min|, H limits H; volumetric VA
// limits va, VAx va_x .... Values in µm, as the file's were converted.
std::map<std::string, ToleranceBand> history_figure_bands(const ToleranceFile& f, const std::vector<std::string>& axes);

}  // namespace mtcal
