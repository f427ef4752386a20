// JSON of the volumetric-accuracy results: VA and critical pairs, contributions, distributions, reduced volumes,
// grouping, diagonals.
#pragma once

#include <cstddef>
#include <vector>

#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// {"from", "to" (configurations), "error_from", "error_to", "difference" ([x, y, z] mm)}
Json to_json(const Machine& m, const ErrorMap& map, const PointPair& pair);

// {"exact", "first_order" ([x, y, z] mm), "residual" (mm), "items": [{"error", "effect", "along",
// "share"}]}, the first `top` items.
Json to_json(const ContributionAnalysis& c, std::size_t top);

// {"count", "mean", "min", "max", "bins", "bin_width", "lo", "counts", "p50", "p90", "p95", "p99"} (mm)
Json to_json(const Distribution& d);

// {"fraction", "lo", "hi", "points", "va"}
Json to_json(const Machine& m, const BoxVa& b);

// {"angle", "magnitude", "groups", "records", "comparisons", "va", "va_exact",
// "difference_percent", "comparison_reduction_percent"}
Json to_json(const GroupingComparison& g, const VolumetricAccuracy& exact);

// The volumetric evaluation: {"machine", "points", "pairs", "va", "va_x", "va_y", "va_z",
// "critical_pair", "component_pairs" {"x", "y", "z"}, "contributions", "distance_evaluations",
// "seconds" {"map", "va", "histogram"}, and as asked "box", "box_scan", "histogram",
// "error_distribution", "grouping"} (docs/volumetric.md).
Json to_json(const Machine& m, const ErrorMap& map, const VolumetricStudy& s, double seconds_map);

// {"mode", "at", "from" (pair modes), "va" (critical_pair), "exact", "first_order", "residual",
// "items" (the first top), "what_if" [{"error", "va_without", "gain", "share", "disagrees", and
// where it disagrees "critical_pair_without" {"from", "to"}, "along_there", "cancelled" [{"error",
// "against": its effect against this error's, mm}], largest first}] (critical_pair, when asked), "correction_sequence"
// {"target_va", "start_va", "reached", "steps" [{"error", "va"}]} (with a target VA); lengths in mm}
Json to_json(const Machine& m, const ContributionStudy& s, std::size_t top);

// {"name", "from", "to", "length", "direction", "range", "position", "deviation"}
Json to_json(const Machine& m, const DiagonalProfile& d);
// {"machine", "diagonals": [...]}
Json to_json(const Machine& m, const std::vector<DiagonalProfile>& diagonals);

}  // namespace mtcal
