// G-code rewriter (formats layer): a program with new coordinates for its moves, everything else of its text kept.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "mtcal/compensation/gcode_correction.hpp"
#include "mtcal/io/gcode.hpp"

namespace mtcal {

struct GcodeRewriteOptions {
  // Digits after the decimal point of a written value in mm or deg (one more under G20: inches).
  int decimals = 6;
};

struct GcodeRewriteSummary {
  std::size_t lines_in = 0;
  std::size_t lines_changed = 0;  // lines of the program whose text changed
  std::size_t lines_added = 0;    // lines written after a move for its further pieces
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

}  // namespace mtcal
