// JSON of a corrected G-code program's summary (compensation/gcode_correction.hpp, io/gcode/rewrite_summary.hpp).
#pragma once

#include "mtcal/compensation/gcode_correction.hpp"
#include "mtcal/io/gcode/rewrite_summary.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// {"moves", "moves_corrected", "subdivisions", "transitions", "arcs_kept", "arcs_linearised",
// "direction_conflicts", "points_solved", "max_correction" (mm), "max_rotary_correction" (deg),
// "max_iterations", "max_residual" (mm), "max_orientation_left" (rad), "max_error_before" (mm),
// "max_deviation_after" (mm), "warnings": [...]} (docs/compensation-gcode.md).
Json to_json(const GcodeCorrectionResult& r);
// {"lines_in", "lines_changed", "lines_added"}
Json to_json(const GcodeRewriteSummary& s);

}  // namespace mtcal
