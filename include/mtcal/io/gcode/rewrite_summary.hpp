// What the G-code rewriter did to a program's text (a record: JSON writers include it, not the rewriter).
#pragma once

#include <cstddef>
#include <string>

namespace mtcal {

struct GcodeRewriteSummary {
  std::size_t lines_in = 0;
  std::size_t lines_changed = 0;  // lines of the program whose text changed
  std::size_t lines_added = 0;    // lines written after a move for its further pieces
};

// A corrected program's text and how it was written (corrected_program in io/gcode/rewrite.hpp).
struct CorrectedProgram {
  std::string text;
  GcodeRewriteSummary summary;
  bool expanded = false;  // every move written anew (write_expanded_gcode), else corrected in place
};

}  // namespace mtcal
