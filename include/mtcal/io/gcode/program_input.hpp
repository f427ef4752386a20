// A G-code program opened with the setup it runs under (tool table, parameter file, work offsets, G28/G30) and the
// interpreter that reads it: mtcal's ISO reader or LinuxCNC's rs274 (what `mtcal toolpath` and `compensate --gcode` do).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

// The tool table of LinuxCNC's sim configuration axis_mm.ini (T1-T10 in mm), which the Debian
// package linuxcnc-uspace installs (dpkg -L linuxcnc-uspace): where tools can come from.
inline constexpr const char* kLinuxcncSimToolTable =
    "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/sim_mm.tbl";

// A work offset given axis by axis: the system (0 for G54 .. 8 for G59.3) and the values of the
// axes named (X Y Z A B C, mm and deg); an axis not named keeps what the parameter file gave.
struct WorkOffsetEntry {
  int system = 0;
  std::array<std::optional<double>, 6> values{};
};

// The index of "G54" .. "G59.3" (0 .. 8); nothing for another name.
std::optional<int> work_system_index(std::string_view name);

// What the setup of a program is made of, in the order LinuxCNC applies it: the parameter file
// (work offsets, G28/G30, the system in effect), then the work offsets given, then G28/G30 given;
// the tool table. Lengths of the files are multiplied by their scale (25.4 for files in inches).
struct GcodeSetupInputs {
  std::string tool_table;  // LinuxCNC tool table, or empty
  double tool_scale = 1.0;
  std::string parameters;  // LinuxCNC parameter file (.var), or empty
  double parameter_scale = 1.0;
  std::vector<WorkOffsetEntry> work_offsets;
  std::optional<GcodePosition> g28, g30;
};

// The setup: reads the files (InputError located in them).
GcodeSetup make_gcode_setup(const GcodeSetupInputs& inputs);

enum class GcodeInterpreter { Auto, Mtcal, Rs274 };
// "auto", "mtcal", "rs274" (InputError located in `field` otherwise).
GcodeInterpreter parse_gcode_interpreter(const std::string& name, const std::string& field = "interpreter");

struct GcodeInputOptions {
  // Auto: mtcal's reader unless the program needs LinuxCNC's interpreter (and that is installed).
  GcodeInterpreter interpreter = GcodeInterpreter::Auto;
  Rs274Options rs274;
  // The interpreter was named by the user: it must exist even where mtcal's reader reads the
  // program (a name given is never ignored). Refused as InputError located in "rs274".
  bool rs274_named = false;
};

// LinuxCNC's interpreter stopped at a tool the tool table lacks (its sample programs select tools):
// what() says where tools come from; interpreter_message() is the interpreter's words alone.
class GcodeToolMissing : public InputError {
 public:
  GcodeToolMissing(SourceLocation where, const std::string& what_happened, std::string interpreter_message)
      : InputError(std::move(where), what_happened), message_(std::move(interpreter_message)) {}
  const std::string& interpreter_message() const noexcept { return message_; }

 private:
  std::string message_;
};

// A program opened for reading: its moves one at a time, and what chose the interpreter.
struct GcodeInput {
  std::string text;  // the program, or the canonical calls of LinuxCNC's interpreter
  GcodeOptions options;
  std::unique_ptr<MoveSource> moves;
  std::string interpreter;  // "mtcal" or "rs274"
  std::string why;          // why rs274 was used (the first word mtcal's reader does not read)
  std::vector<std::string> notes;
};

// Reads the setup files, chooses the interpreter, runs it on the program at `path` (axes: the
// machine's axis letters, e.g. "XYZBC"). Throws InputError/Error with what to do: a program that
// needs LinuxCNC's interpreter when it is not installed, a lathe program, the interpreter's errors.
GcodeInput open_gcode(const std::string& path, const std::string& axes, const GcodeSetupInputs& setup,
                      const GcodeInputOptions& options = {});
// The whole program at once (for work that needs every move before it starts); the notes of the
// reading come first among its warnings.
GcodeProgram read_gcode_program(const std::string& path, const std::string& axes, const GcodeSetupInputs& setup,
                                const GcodeInputOptions& options = {});

}  // namespace mtcal
