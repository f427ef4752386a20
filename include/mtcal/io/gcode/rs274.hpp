// LinuxCNC's standalone G-code interpreter rs274 (formats layer): run it on a program, read the canonical machining
// calls it prints as moves.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/io/gcode/reader.hpp"

namespace mtcal {

struct Rs274Options {
  // The interpreter: a path, or a name looked up on PATH (Debian package linuxcnc-uspace).
  std::string executable = "rs274";
  double timeout = 300;                           // s before the run is stopped
  std::size_t max_output = std::size_t{1} << 30;  // bytes of canonical calls before the run is stopped
};

// The interpreter's full path; empty when it is not installed.
std::string find_rs274(const std::string& executable = "rs274");

// What the interpreter printed for a program: its canonical calls (stdout), and whether it stopped
// at the end of the file without M2/M30 or '%' (it reads up to there; LinuxCNC reports this).
struct Rs274Output {
  std::string calls;
  bool missing_end = false;
};

// Runs the interpreter on the program (rs274 -g -t TOOLS -v PARAMETERS PROGRAM; no shell) in the
// program's folder, so that the subroutine files it calls by name are found there. The program
// goes in as a copy whose lines begin with "N<line>", which the interpreter prints with each call,
// so that moves keep their source lines. The setup goes in as a LinuxCNC tool table and parameter
// file written in a private temporary folder, in inches: the standalone interpreter's machine
// units (its GET_EXTERNAL_LENGTH_UNITS); they are never the user's files, which the interpreter
// would rewrite. Throws InputError with the interpreter's message and the program's line when it
// stops on an error, Error when it cannot be started, times out or prints too much.
Rs274Output run_rs274(const std::string& program_path, const GcodeSetup& setup, const Rs274Options& options = {});

// The program's text with "N<line> " at the start of each line that has none (after blanks and
// '/'), a line's own N number replaced; '%' lines kept as they are.
std::string number_gcode_lines(std::string_view text);

// Reader of the canonical calls of LinuxCNC's interpreter (LinuxCNC src/emc/sai/saicanon.cc: one
// call a line, "<count> N<line>|N..... NAME(args)"): STRAIGHT_TRAVERSE, STRAIGHT_FEED and ARC_FEED
// become moves; USE_LENGTH_UNITS, SELECT_PLANE, SET_G5X_OFFSET, SET_G92_OFFSET,
// USE_TOOL_LENGTH_OFFSET, SET_FEED_RATE, CHANGE_TOOL and SET_SPINDLE_SPEED are followed so that
// the moves are in the frame of the setup: program position + work offset + G92 offset + tool
// length offset, mm and deg. Calls whose motion cannot be simulated are refused (InputError):
// probing, spindle-synchronised motion (threading, lathe), rigid tapping, NURBS, a rotated XY
// plane. Calls that move nothing are counted; unknown ones give warnings.
class CanonReader : public MoveSource {
 public:
  CanonReader(std::string_view calls, std::string source, GcodeOptions options = {});
  bool next(GcodeMove& move) override;
  const GcodeCounts& counts() const override { return counts_; }
  const std::string& source() const override { return source_; }
  const std::vector<std::string>& warnings() const override { return warnings_; }

 private:
  [[noreturn]] void fail(const std::string& what) const;
  void warn(const std::string& what);

  std::string_view text_;
  std::string source_;
  GcodeOptions options_;
  std::size_t pos_ = 0;
  int row_ = 0;   // line of the interpreter's output
  int line_ = 0;  // the program's line of the call (0: unknown)
  GcodeCounts counts_;
  std::vector<std::string> warnings_;
  bool inches_ = false;
  GcodePlane plane_ = GcodePlane::XY;
  GcodePosition g5x_{}, g92_{}, length_{};
  GcodePosition position_{};  // program coordinates as the interpreter prints them
  double feed_ = 0;           // mm/min
  int tool_ = -1;
  double spindle_ = 0;
};

// The moves of a program through the interpreter at once: runs it and reads its calls.
GcodeProgram read_gcode_rs274(const std::string& path, const GcodeOptions& options, const Rs274Options& rs274 = {});
GcodeProgram parse_canon(std::string_view calls, const std::string& source, const GcodeOptions& options = {});

}  // namespace mtcal
