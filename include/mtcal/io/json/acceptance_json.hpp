// JSON of the acceptance records: report metadata and the tolerance verdict (docs/reports.md).
#pragma once

#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// {"machine": "...", ...} in metadata_fields() order.
Json to_json(const ReportMetadata& m);
// {"verdict": "pass"|"fail", "unit": "um", "checks": [{"quantity", "value", "limit", "pass"}]}.
Json to_json(const ToleranceVerdict& v);

}  // namespace mtcal
