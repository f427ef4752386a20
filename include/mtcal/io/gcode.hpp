// G-code reader (formats layer): the RS274 subset of straight and circular moves (G0 G1 G2 G3), planes, units and
// distance modes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"

namespace mtcal {

struct GcodeOptions {
  // Axis letters the machine has (any order, e.g. "XYZBC"); a word for another axis is an error.
  std::string axes = "XYZABC";
  // Position before the first move, program coordinates (mm, deg).
  GcodePosition start{};
};

// Arc end-radius tolerance: |r_start - r_end| may be max(kArcRadiusTolerance, kArcRadiusRelative
// r); R may be shorter than half the chord by as much before it is an error.
inline constexpr double kArcRadiusTolerance = 0.002;  // mm
inline constexpr double kArcRadiusRelative = 1e-4;

// Streaming reader over the text (which must outlive it): one move at a time, so that a program
// of any length is read in constant memory. Every error is an InputError with the source name
// and line, and the column in its message ("column 7: ...").
class GcodeReader : public MoveSource {
 public:
  GcodeReader(std::string_view text, std::string source, GcodeOptions options = {});
  // The next block that moves; false at the end of the program.
  bool next(GcodeMove& move) override;
  const GcodeCounts& counts() const override { return counts_; }
  const std::string& source() const override { return source_; }

  // One word of a block as written: its letter (upper case), value, 1-based column of the letter
  // and length in characters up to the end of its number (blanks between them included).
  struct Word {
    char letter;
    double value;
    int column;
    int length = 0;
  };
  // Block by block, for a program rewriter (io/gcode_rewrite.hpp): the next line with words,
  // applied to the modal state; `moved` says whether it moves (then `move` is filled). false at
  // the end of the program. next() and next_block() read the same stream.
  bool next_block(GcodeMove& move, bool& moved);
  // The last block read: its words in line order, its line's text (without the line end) and
  // 1-based line number; the modes in effect after it.
  const std::vector<Word>& block_words() const { return words_; }
  std::string_view block_text() const { return text_.substr(block_begin_, block_end_ - block_begin_); }
  int block_line() const { return line_; }
  bool inches() const { return inches_; }
  bool incremental() const { return incremental_; }
  int motion_mode() const { return motion_; }  // 0 1 2 3, or -1 before any motion code
  GcodePlane plane() const { return plane_; }

 private:
  bool read_block();  // words of the next line with any, into words_; false at the end
  [[noreturn]] void fail(int column, const std::string& what) const;
  bool apply_block(GcodeMove& move);

  std::string_view text_;
  std::string source_;
  GcodeOptions options_;
  std::array<bool, 26> allowed_{};
  std::size_t pos_ = 0;
  std::size_t block_begin_ = 0, block_end_ = 0;  // the last block's line in text_
  int line_ = 0;
  bool opened_ = false;  // a leading % was read
  bool closed_ = false;  // a trailing % was read
  std::vector<Word> words_;
  GcodeCounts counts_;
  // Modal state.
  int motion_ = -1;  // 0 1 2 3 or -1 before any motion code
  GcodePlane plane_ = GcodePlane::XY;
  bool incremental_ = false;
  bool inches_ = false;
  double feed_ = 0;
  GcodePosition position_{};
};

// The whole program at once (a million blocks take about 200 MB; use GcodeReader to stream).
GcodeProgram parse_gcode(std::string_view text, const std::string& source, const GcodeOptions& options = {});
GcodeProgram read_gcode(const std::string& path, const GcodeOptions& options = {});

}  // namespace mtcal
