// G-code reader (formats layer): the portable ISO 6983-1 dialect (moves, arcs, planes, units, distance modes, work
// offsets, tool length, G28/G30, canned cycles G73 G81-G89) and the setup files it needs (tool table, parameters).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

// One tool of a tool table: its offsets along X Y Z A B C (Z: the tool length, what G43 applies;
// mm and deg) and diameter (mm), with the table's line.
struct GcodeTool {
  GcodePosition offset{};
  double diameter = 0;
  int line = 0;
};

// The machine's setup a program runs under (what a control keeps between programs), in the frame
// the moves are given in: the axis positions the control commands, mm and deg.
struct GcodeSetup {
  // G54 G55 G56 G57 G58 G59 G59.1 G59.2 G59.3: where each work coordinate system's zero is.
  std::array<GcodePosition, 9> work_offsets{};
  int work_system = 0;  // the one in effect at the start: 0 for G54
  // The positions G28 and G30 return to (LinuxCNC parameters 5161-5166 and 5181-5186).
  GcodePosition g28{}, g30{};
  std::map<int, GcodeTool> tools;  // by tool number
  bool has_tool_table = false;     // a table was given (else G43 H has no length to take)
};

// Names of the work coordinate systems, "G54" .. "G59.3", by index.
std::string_view work_system_name(int index);

struct GcodeOptions {
  // Axis letters the machine has (any order, e.g. "XYZBC"); a word for another axis is an error.
  std::string axes = "XYZABC";
  // Position before the first move, in the frame of the moves (mm, deg).
  GcodePosition start{};
  GcodeSetup setup;
};

// A program that needs the full RS274NGC language (parameters, expressions, O-word control flow)
// or a feature of LinuxCNC that the ISO dialect has not (cutter radius compensation, G92, ...):
// LinuxCNC's interpreter can read it (io/gcode/rs274.hpp).
class GcodeNeedsInterpreter : public InputError {
 public:
  using InputError::InputError;
};

// A lathe program (diameter mode, lathe cycles, threading, constant surface speed): mtcal
// simulates milling machines.
class GcodeLatheProgram : public InputError {
 public:
  using InputError::InputError;
};

// A LinuxCNC tool table (LinuxCNC documentation, "Tool Table Format"): one tool a line,
// "T<number> P<pocket> [X.. Y.. Z.. A.. B.. C.. U.. V.. W..] [D<diameter>] [I.. J.. Q..] [;comment]",
// in the machine's units, here mm and deg (`scale` converts lengths: 25.4 for a table in inches).
std::map<int, GcodeTool> parse_tool_table(std::string_view text, const std::string& source, double scale = 1.0);
std::map<int, GcodeTool> read_tool_table(const std::string& path, double scale = 1.0);

// A LinuxCNC parameter file (".var": "<number> <value>" a line) into `setup`: the work offsets
// (parameters 5221-5226 for G54, 20 apart up to 5381 for G59.3), the G28 and G30 positions
// (5161-5166, 5181-5186) and the coordinate system in effect (5220: 1 for G54 .. 9 for G59.3).
// Lengths are multiplied by `scale`; other parameters are kept by LinuxCNC only and skipped.
void parse_parameter_file(std::string_view text, const std::string& source, GcodeSetup& setup, double scale = 1.0);
void read_parameter_file(const std::string& path, GcodeSetup& setup, double scale = 1.0);

// Arc end-radius tolerance: |r_start - r_end| may be max(kArcRadiusTolerance, kArcRadiusRelative
// r); R may be shorter than half the chord by as much before it is an error.
inline constexpr double kArcRadiusTolerance = 0.002;  // mm
inline constexpr double kArcRadiusRelative = 1e-4;

// Streaming reader over the text (which must outlive it): one move at a time, so that a program
// of any length is read in constant memory. Every error is an InputError with the source name
// and line, and the column in its message ("column 7: ..."); GcodeNeedsInterpreter for what only
// LinuxCNC's interpreter reads, GcodeLatheProgram for lathe work. Moves are in the frame of the
// setup: program coordinates plus the work offset in effect plus the tool length (G43); words
// that change nothing simulated (M, S, T, G61, G64 ...) are counted, unknown ones give warnings.
class GcodeReader : public MoveSource {
 public:
  GcodeReader(std::string_view text, std::string source, GcodeOptions options = {});
  // The next block that moves; false at the end of the program.
  bool next(GcodeMove& move) override;
  const GcodeCounts& counts() const override { return counts_; }
  const std::string& source() const override { return source_; }
  const std::vector<std::string>& warnings() const override { return warnings_; }

  // One word of a block as written: its letter (upper case), value, 1-based column of the letter
  // and length in characters up to the end of its number (blanks between them included).
  struct Word {
    char letter;
    double value;
    int column;
    int length = 0;
  };
  // Block by block, for a program rewriter (io/gcode/rewrite.hpp): the next line with words,
  // applied to the modal state; `moved` says whether it moves (then `move` is its first move and
  // block_moves() all of them). false at the end of the program. next() and next_block() read
  // the same stream.
  bool next_block(GcodeMove& move, bool& moved);
  const std::vector<GcodeMove>& block_moves() const { return out_; }
  // The last block read: its words in line order, its line's text (without the line end) and
  // 1-based line number; the modes in effect after it.
  const std::vector<Word>& block_words() const { return words_; }
  std::string_view block_text() const { return text_.substr(block_begin_, block_end_ - block_begin_); }
  int block_line() const { return line_; }
  bool inches() const { return inches_; }
  bool incremental() const { return incremental_; }
  int motion_mode() const { return motion_; }  // 0 1 2 3, 73 81-89 (cycles), 80, or -1 before any motion code
  GcodePlane plane() const { return plane_; }

 private:
  bool read_block();  // words of the next line with any, into words_; false at the end
  [[noreturn]] void fail(int column, const std::string& what) const;
  [[noreturn]] void needs_interpreter(int column, const std::string& what) const;
  [[noreturn]] void lathe(int column, const std::string& what) const;
  void warn(int column, const std::string& word, const std::string& why);
  bool apply_block();
  // A straight move to `end` (frame of the moves), appended to out_ unless it goes nowhere.
  void emit_line(bool rapid, const GcodePosition& end);
  double offset(std::size_t slot) const { return work_[slot] + length_[slot]; }

  std::string_view text_;
  std::string source_;
  GcodeOptions options_;
  std::array<bool, 26> allowed_{};
  std::size_t pos_ = 0;
  std::size_t block_begin_ = 0, block_end_ = 0;  // the last block's line in text_
  int line_ = 0;
  bool opened_ = false;  // a leading % was read
  bool closed_ = false;  // a trailing % was read
  bool ended_ = false;   // M2 or M30 was read
  int end_line_ = 0;
  std::vector<Word> words_;
  GcodeCounts counts_;
  std::vector<std::string> warnings_;
  std::vector<GcodeMove> out_;  // the moves of the last block
  std::size_t out_next_ = 0;    // the next of them next() gives
  GcodeMove proto_;             // what the block's moves share (line, n, feed, tool, ...)
  // Modal state.
  int motion_ = -1;  // 0 1 2 3, 73 81-89, 80, or -1 before any motion code
  GcodePlane plane_ = GcodePlane::XY;
  bool incremental_ = false;
  bool arc_absolute_ = false;  // G90.1: I J K are positions, not offsets from the start
  bool inches_ = false;
  double feed_ = 0;
  int tool_ = -1, selected_tool_ = -1;
  double spindle_ = 0;
  GcodePosition position_{};  // frame of the moves
  GcodePosition work_{};      // the work offset in effect
  GcodePosition length_{};    // the tool length offset in effect (G43)
  int work_system_ = 0;
  // Canned cycles: the sticky R, the depth (the normal axis' word), Q and P, and the level of the
  // normal axis before the series of cycles began (G98 returns there).
  bool retract_initial_ = true;  // G98 (the default, as in LinuxCNC) or G99
  double cycle_r_ = 0, cycle_depth_ = 0, cycle_q_ = 0, cycle_p_ = 0;
  bool cycle_r_set_ = false, cycle_depth_set_ = false;
  double cycle_initial_ = 0;
  bool in_cycle_series_ = false;
};

// The whole program at once (a million blocks take about 200 MB; use GcodeReader to stream).
GcodeProgram parse_gcode(std::string_view text, const std::string& source, const GcodeOptions& options = {});
GcodeProgram read_gcode(const std::string& path, const GcodeOptions& options = {});

// Throws GcodeLatheProgram at the first word, written as a number, that only a lathe runs: G7 G8
// (diameter, radius mode), G70 G71 G72 (lathe cycles), G76 (threading), G96 (constant surface
// speed). A lexical scan, comments skipped, for programs read by LinuxCNC's interpreter, whose
// canonical calls do not tell a lathe's X from a mill's.
void refuse_lathe_program(std::string_view text, const std::string& source);

// Whether mtcal's reader cannot read the program but LinuxCNC's interpreter can (parameters,
// expressions, O-word subroutines, loops and conditions, cutter radius compensation, G92 ...):
// the first such word, located, when so; nothing when mtcal's reader reads it. Any other error
// of the program is thrown as parse_gcode throws it.
std::optional<GcodeNeedsInterpreter> gcode_needs_interpreter(std::string_view text, const std::string& source,
                                                             const GcodeOptions& options = {});

}  // namespace mtcal
