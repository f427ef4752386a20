// G-code rewriter (formats layer): a program with new coordinates for its moves, everything else of its text kept.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "mtcal/compensation/gcode_correction.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/rewrite_summary.hpp"

namespace mtcal {

struct GcodeRewriteOptions {
  // Digits after the decimal point of a written value in mm or deg (one more under G20: inches).
  int decimals = 6;
};

// The program `text` (read with `options`, the reading that gave the moves that were corrected)
// with each move's pieces written in place of its coordinates (docs/compensation-gcode.md):
// - the move's own line carries the first piece: its axis words get the new values, in the
//   line's units (G20/G21) and distance mode (G90: positions, G91: increments from the
//   position written before), axis words are added for axes whose value changes, I J K or R
//   describe the piece's arc (they are removed when the piece is straight) and the motion word
//   is changed or added when the piece's motion differs from the one in effect. A word whose
//   new value rounds to the value it means already keeps its text; every other character of
//   the line (N, F, S, T, M, other G words, comments, spacing) is kept;
// - each further piece is a line of its own after it: "G1 X.. Y.." (or "G2/G3 .. I.. J..")
//   with the words of the axes that change, ended like the move's line;
// - every other line is copied as it is.
// Values are written with `decimals` digits and always a decimal point ("10.0", never "10",
// which some controls read as increments of their resolution).
// Throws InputError as GcodeReader does, Error if the moves do not belong to this program.
std::string rewrite_gcode(std::string_view text, const std::string& source, const GcodeOptions& options,
                          std::span<const CorrectedMove> moves, const GcodeRewriteOptions& rewrite = {},
                          GcodeRewriteSummary* summary = nullptr);

// The corrected moves as a program of its own, for a program whose text cannot take them in
// place: one read by LinuxCNC's interpreter (subroutines, loops, expressions), or with canned
// cycles, G28/G30 or G53 (one block, several moves), or moves under a work offset or tool length
// (docs/gcode.md). `program` is the reading the moves were corrected from (same order). Written:
// a header of comments saying what the program is, "G21 G90 G94 G40 G49 G80 G17", then every piece
// as a line "G0/G1 X.. Y.. .." or "G2/G3 .. I J K" (centre offsets from the start) with the
// machine's axes (`axes`), absolute, mm and deg, in the frame of the moves: work offsets and tool
// lengths included, so that it runs with the program zero where the original's frame has it and
// no tool length offset; F where the feed changes; "(line N)" naming the original's line. Spindle,
// coolant and tool changes are not written (the header says so); a tool change is a comment.
std::string write_expanded_gcode(std::span<const CorrectedMove> moves, const GcodeProgram& program,
                                 const std::string& axes, const std::string& title,
                                 const GcodeRewriteOptions& rewrite = {}, GcodeRewriteSummary* summary = nullptr);

// The corrected program of `mtcal compensate --gcode` (docs/compensation-gcode.md): `text`, the
// program file that `program` was read from with the machine's axis letters, with new coordinates
// (rewrite_gcode) when mtcal's reader read it and each block is its one move in program
// coordinates (no block expanded into several moves, no work offset or tool length in effect);
// else every move written anew (write_expanded_gcode) under a title naming the machine. `text`
// is read only in the first case. Throws as rewrite_gcode does.
CorrectedProgram corrected_program(const Machine& m, const GcodeProgram& program, std::string_view text,
                                   std::span<const CorrectedMove> moves, const GcodeRewriteOptions& rewrite = {});

}  // namespace mtcal
