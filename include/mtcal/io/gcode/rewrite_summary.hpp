// What the G-code rewriter did to a program's text (a record: JSON writers include it, not the rewriter).
#pragma once

#include <cstddef>

namespace mtcal {

struct GcodeRewriteSummary {
  std::size_t lines_in = 0;
  std::size_t lines_changed = 0;  // lines of the program whose text changed
  std::size_t lines_added = 0;    // lines written after a move for its further pieces
};

}  // namespace mtcal
