// JSON of the acceptance-test evaluations: ISO 230-2 positioning, ISO 230-4 circular tests, method comparison.
#pragma once

#include <optional>
#include <string>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// A B R E M (with _up/_down; null where the test does not define them), unit, target_unit,
// runs, directions, notes, targets[] (docs/evaluations.md, "JSON keys"). Full precision.
Json to_json(const PositioningEvaluation& e);

// One direction's path: points, G, G_minimum_zone, centre, minimum_zone_centre, F_max, F_min, F_mean.
Json to_json(const CircularDeviation& d);
// {term name: {value, u, unit, share}} in the model's order.
Json to_json(const TraceDiagnosis& d);
// The circular test: plane, radius, feed (when > 0), G_cw G_ccw G_b H F_max F_min
// F_mean_bidirectional (null where not evaluated), cw, ccw, diagnostics and
// diagnostics_residual_rms_um (with a diagnosis), units.
Json to_json(const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis, const std::string& plane,
             double radius, double feed);

// file, methods, parameters {name: mean stdev abs_diff overlap pearson_r n paired}, summary.
Json to_json(const MethodComparison& c);

}  // namespace mtcal
