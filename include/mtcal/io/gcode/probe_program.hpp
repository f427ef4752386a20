// The probing program of a plan (docs/planning.md): G-code for LinuxCNC (G38.2, PROBEOPEN log) or an ISO control (G31).
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/planning.hpp"
#include "mtcal/identification/sphere_locate.hpp"

namespace mtcal {

enum class ProbeDialect { LinuxCNC, Iso };

// What the program's X Y Z mean. Axes: the machine's axis values (a controller without
// tool-centre-point kinematics, LinuxCNC trivkins). ToolPoint: the world of a tool-centre-point
// kinematics (LinuxCNC trt-kins, mtcal's linuxcnc-kins module): X Y Z the nominal tool point in the
// workpiece frame, the rotary words the rotary axes (ToolPointCoordinates). The same program then
// runs unchanged on the nominal kinematics and on a compensating module.
enum class ProbeCoordinates { Axes, ToolPoint };

struct ProbeProgramOptions {
  ProbeDialect dialect = ProbeDialect::LinuxCNC;
  double probe_feed = 200.0;  // mm/min of the probing moves
  double feed = 2000.0;       // mm/min of the moves near the artefact (G1)
  std::string log = "mtcal-contacts.txt";  // LinuxCNC: the file PROBEOPEN writes
  std::string header;  // a line for the header comment (machine, plan); parentheses become brackets
  std::vector<std::string> notes;  // further header comment lines, one each (as the header)
  ProbeCoordinates coordinates = ProbeCoordinates::Axes;
  // ToolPoint: the largest rotary step of one indexing block (rad). An indexation is a rotary move at
  // the safe level; in tool-point coordinates a block that turns the rotary axes keeps the tool point
  // still on the workpiece (the linear axes swing round), so the turn is written as blocks that follow
  // the axes' own path: linear axes held at the safe level, the rotary ones in steps of at most this.
  double index_step = 5.0 * 3.14159265358979323846 / 180.0;
};

// The program: a header that states the coordinates (the machine's axis values of mtcal's model,
// mm and deg: G54 offsets zero, no tool length offset, G49) and the cycle; per record a retract of
// the tool-axis linear axis to its travel end, the indexation (G0 of the rotary axes), a G0 over the
// first touch's start at the safe level and a G0 down to the clearance level (probe_clearance_level);
// then per touch the G1 moves to its start (between a ball's touches over the clearance level), the
// probing move (G38.2 / G31 at probe_feed) and the G1 retract. estimate_time sums these blocks. LinuxCNC: (PROBEOPEN log) ... (PROBECLOSE) around the touches, which makes LinuxCNC
// write one line of the 9 probed coordinates per G38.2 (LinuxCNC G-code overview, "Probe
// Logging"). ISO: the skip position #5061-#5063 after each G31 is to be written as one CSV line
// (read_probe_log, ProbeLogFormat::IsoCsv). Every move is a full-word absolute block (G90).
// ToolPoint coordinates: every position is the world position of the same axis values (above); the
// program starts with a move to the rotary axes' zero at the safe level and indexes in steps.
std::string probe_program(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                          const ProbeProgramOptions& options);
// probe_program written to path (complete or not at all).
void write_probe_program(const std::string& path, const Machine& m, const ProbingPlan& plan,
                         const ProbeCycle& cycle, const ProbeProgramOptions& options);

// The locating program (docs/planning.md, "Locating the sphere"): the same program frame as
// probe_program (header, coordinates, PROBEOPEN log or ISO skip positions, safe retract, indexing)
// with the touches of locate_touches for each record of a locate_plan; between a ball's touches the
// probe changes over (rho + within + clearance) above the rough centre, where no sphere within
// `within` can be.
std::string locate_program(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                           const LocateOptions& locate, const ProbeProgramOptions& options);
void write_locate_program(const std::string& path, const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                          const LocateOptions& locate, const ProbeProgramOptions& options);

}  // namespace mtcal
