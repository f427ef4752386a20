// JSON of a tool-path simulation's summary.
#pragma once

#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// {"points", "blocks", "path_length" (mm), "ignored_words", "rapids_skipped", "max_error": {"value"
// (mm), "line", "at"}, "range": {"dx": [min, max], ... "rz"}} (docs/toolpath.md); null where there
// was no point.
Json to_json(const Machine& m, const ToolpathSummary& s);

}  // namespace mtcal
