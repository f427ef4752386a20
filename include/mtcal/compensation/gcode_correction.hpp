// Corrected G-code: the commanded positions that put the actual tool where a program asks, with moves subdivided where
// the correction varies.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// What the caller asks of a correction (docs/compensation-gcode.md).
struct GcodeCorrectionOptions {
  // Largest distance (mm) allowed between the actual tool point of a corrected piece and the
  // programmed point at the same progress, checked at 7 points inside every piece; a move is
  // cut into pieces until it holds.
  double max_deviation = 0.001;
  // Write arcs as straight pieces (chords); otherwise arcs stay arcs, cut into shorter arcs
  // where the correction is not constant enough along them.
  bool linearise_arcs = false;
  // Correct with each axis's direction of motion (the reversal terms of the motion errors), as
  // the tool-path simulation evaluates; false: direction 0 (the mean of forward and backward).
  bool directions = true;
  // Correct the tool's orientation with the rotary axes, where the machine has them; false:
  // the rotary axes keep their programmed values and only the tool point is corrected.
  bool orientation = true;
  // Weight (rad of orientation per rad of rotary-axis correction) that keeps rotary corrections
  // small near a kinematic singularity (a tool axis along a rotary axis): damped least squares.
  double rotary_damping = 1e-2;
  // The solver stops when the tool point is within this of its target (mm).
  double tolerance = 1e-9;
  int max_iterations = 50;
  // A move may not be cut into more pieces than this.
  std::size_t max_pieces_per_move = 100000;
  // Machine axis positions of program zero (mm, deg), as ToolpathOptions::origin.
  GcodePosition origin{};
  bool travel_check = true;  // every commanded position inside its axes' travels
};

// One move of the corrected program. Its start is the previous piece's end (the uncorrected
// program start before the first). Program coordinates, mm and deg, as GcodeMove.
struct CorrectedPiece {
  GcodeMotion motion = GcodeMotion::Linear;
  GcodePosition end{};
  std::array<double, 3> centre{};  // arcs: as GcodeMove::centre
  double sweep = 0;                // arcs: signed, rad
  // The part [t0, t1] of the original move this piece follows (progress as position_at).
  double t0 = 0, t1 = 1;
  // A reversal move inserted at a point where an axis changes direction: the tool stays at the
  // programmed point while the correction of the new direction is taken up (t0 == t1).
  bool transition = false;
};

// The corrected form of one original move (same order as the program's moves).
struct CorrectedMove {
  int line = 0;
  GcodeMotion motion = GcodeMotion::Linear;  // the original's
  std::vector<CorrectedPiece> pieces;        // at least one
  bool linearised = false;                   // an arc written as straight pieces
};

struct GcodeCorrectionResult {
  std::vector<CorrectedMove> moves;
  std::size_t moves_corrected = 0;      // moves whose end changed
  std::size_t subdivisions = 0;         // pieces written beyond one per move (transitions included)
  std::size_t transitions = 0;          // reversal moves inserted
  std::size_t arcs_kept = 0;            // arcs written as (one or more) arcs
  std::size_t arcs_linearised = 0;      // arcs written as straight pieces
  std::size_t direction_conflicts = 0;  // points where no command moves each axis in the direction it was solved for
  double max_correction = 0;            // largest |commanded - programmed| of X Y Z (mm)
  double max_rotary_correction = 0;     // largest |commanded - programmed| of A B C (deg)
  int max_iterations = 0;               // of the solver, over every point solved
  std::size_t points_solved = 0;
  double max_residual = 0;          // largest |actual - programmed tool point| at a solved point (mm)
  double max_orientation_left = 0;  // largest tool-orientation error left at a solved point (rad)
  double max_error_before = 0;  // largest |actual - programmed tool point| of the original, at the points checked (mm)
  double max_deviation_after = 0;  // largest deviation of the corrected pieces, at the points checked (mm)
  std::vector<std::string> warnings;
};

// Solves, for every programmed point, the command x_cmd with actual(x_cmd) = nominal(x_target):
// the tool point (and, with the rotary axes, the tool's direction) where the program puts it
// (docs/compensation-gcode.md). Moves are cut into pieces until each stays within
// max_deviation. Rapids are corrected at their ends only. Throws InputError (program:line) for
// a point that does not converge, a move that cannot be cut finely enough, a commanded point
// outside the travel; ModelError for a machine without the three linear axes X Y Z.
GcodeCorrectionResult correct_program(const ErrorModel& model, const GcodeProgram& program,
                                      const GcodeCorrectionOptions& options = {});

}  // namespace mtcal
