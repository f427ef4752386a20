#include "mtcal/io/json/gcode_correction_json.hpp"

namespace mtcal {

Json to_json(const GcodeCorrectionResult& r) {
  Json j;
  j["moves"] = r.moves.size();
  j["moves_corrected"] = r.moves_corrected;
  j["subdivisions"] = r.subdivisions;
  j["transitions"] = r.transitions;
  j["arcs_kept"] = r.arcs_kept;
  j["arcs_linearised"] = r.arcs_linearised;
  j["direction_conflicts"] = r.direction_conflicts;
  j["points_solved"] = r.points_solved;
  j["max_correction"] = number_or_null(r.max_correction);
  j["max_rotary_correction"] = number_or_null(r.max_rotary_correction);
  j["max_iterations"] = r.max_iterations;
  j["max_residual"] = number_or_null(r.max_residual);
  j["max_orientation_left"] = number_or_null(r.max_orientation_left);
  j["max_error_before"] = number_or_null(r.max_error_before);
  j["max_deviation_after"] = number_or_null(r.max_deviation_after);
  j["warnings"] = r.warnings;
  return j;
}

Json to_json(const GcodeRewriteSummary& s) {
  Json j;
  j["lines_in"] = s.lines_in;
  j["lines_changed"] = s.lines_changed;
  j["lines_added"] = s.lines_added;
  return j;
}

Json to_json(const Machine& m, const std::string& program, const std::string& interpreter,
             const GcodeCorrectionResult& r, const CorrectedProgram& c, double seconds, const std::string& out) {
  Json j;
  j["machine"] = m.name;
  j["program"] = program;
  j["interpreter"] = interpreter;
  j["written"] = c.expanded ? "expanded" : "in_place";
  j["correction"] = to_json(r);
  j["rewrite"] = to_json(c.summary);
  j["seconds"] = seconds;
  j["out"] = out;
  return j;
}

}  // namespace mtcal
