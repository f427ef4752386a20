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

// The summary `mtcal compensate --gcode --json` prints: {"machine", "program" (the file),
// "interpreter" (who read it: "mtcal" or "rs274"), "written" ("expanded" or "in_place"),
// "correction", "rewrite", "seconds", "out" (the file written)}.
Json to_json(const Machine& m, const std::string& program, const std::string& interpreter,
             const GcodeCorrectionResult& r, const CorrectedProgram& c, double seconds, const std::string& out);

}  // namespace mtcal
