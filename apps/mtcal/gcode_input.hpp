// Reading a G-code program on the command line: which interpreter (mtcal's ISO reader or LinuxCNC's rs274) and the
// setup it runs under.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal::cli {

struct GcodeInputOptions {
  std::string interpreter = "auto";  // auto | mtcal | rs274
  std::string rs274 = "rs274";
  double rs274_timeout = 300;
  std::string tool_table, tool_units = "mm", parameters, parameter_units = "mm", g28, g30;
  std::vector<std::string> work_offsets;    // "G55:X=100,Y=50"
  std::vector<const CLI::Option*> options;  // as added, to tell which were given
};

// --interpreter --rs274 --tool-table --tool-units --parameters --parameter-units --work-offset
// --g28 --g30.
void add_gcode_input_options(CLI::App* app, GcodeInputOptions& o);

// Refuses options given without a program to act on (they would be ignored silently).
void check_gcode_input_options(const GcodeInputOptions& o, bool program_given);

// The files the options name (for the input/output checks).
std::vector<std::string> gcode_input_files(const GcodeInputOptions& o);

// A program opened for reading: its moves one at a time, and what chose the interpreter.
struct GcodeInput {
  std::string text;  // the program, or the canonical calls of LinuxCNC's interpreter
  GcodeOptions options;
  std::unique_ptr<MoveSource> moves;
  std::string interpreter;  // "mtcal" or "rs274"
  std::string why;          // why rs274 was used (the first word mtcal's reader does not read)
  std::vector<std::string> notes;
};

// Reads the setup files, chooses the interpreter (auto: mtcal's reader unless the program needs
// LinuxCNC's and that is installed), runs it. Throws InputError/Error with what to do.
GcodeInput open_gcode(const std::string& path, const Machine& m, const GcodeInputOptions& o);
// The whole program at once (for commands that need every move before they start).
GcodeProgram read_gcode_program(const std::string& path, const Machine& m, const GcodeInputOptions& o);

// Warnings of the reading on stderr ("mtcal: warning: ..."), the count of those not shown.
void print_gcode_warnings(const std::vector<std::string>& warnings, std::size_t total);

}  // namespace mtcal::cli
