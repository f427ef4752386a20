// JSON summary of a compensation target's output (`mtcal compensate --json`): what its numbers are, its
// files, what it cannot hold and the residual. Apart from io/compensation/output.hpp so that the
// controller writers do not compile nlohmann-json.
#pragma once

#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// {"target", "quantity", "sign_source", "files": [...], "not_compensated": [{what, max_error,
// unit}], "warnings": [...], "residual": {configurations, max_before_mm: [x,y,z], max_after_mm,
// max_norm_before_mm, max_norm_after_mm, va_before_mm, va_after_mm}}
Json to_json(const TargetOutput& output);

}  // namespace mtcal
