// Reading a G-code program on the command line: the options that name the interpreter (mtcal's ISO reader or
// LinuxCNC's rs274) and the setup it runs under, turned into the library's (io/gcode/program_input.hpp).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/io/gcode/program_input.hpp"
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

// The library's setup and interpreter options from the command's (errors located in the options).
GcodeSetupInputs gcode_setup_inputs(const Machine& m, const GcodeInputOptions& o);
mtcal::GcodeInputOptions gcode_input_options(const GcodeInputOptions& o);

// The library's open_gcode / read_gcode_program with the command's options; what to do is said
// in the options' words.
GcodeInput open_gcode(const std::string& path, const Machine& m, const GcodeInputOptions& o);
GcodeProgram read_gcode_program(const std::string& path, const Machine& m, const GcodeInputOptions& o);

// Warnings of the reading on stderr ("mtcal: warning: ..."), the count of those not shown.
void print_gcode_warnings(const std::vector<std::string>& warnings, std::size_t total);

}  // namespace mtcal::cli
