// The corrected G-code program's command-line part: options and run, for `mtcal compensate --gcode`.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "common.hpp"
#include "gcode_input.hpp"

namespace mtcal::cli {

struct GcodeCorrectionCliOptions {
  ModelOptions model;  // --machine, --params ... (added by the caller when it has them already)
  GcodeInputOptions input;
  std::string gcode, out, origin;
  double max_deviation = 0.001;
  int decimals = 6;
  bool linearise_arcs = false, json_out = false, no_direction = false, no_orientation = false, no_travel_check = false;
};

// The options of the corrected program (--gcode --out --max-deviation --linearise-arcs --origin
// --decimals --no-direction --no-orientation --no-travel-check --json), not the model options.
void add_gcode_correction_options(CLI::App& app, GcodeCorrectionCliOptions& o);
// Loads the machine and the program, corrects it, writes --out completely or not at all, prints
// the summary (text or --json). Returns the exit status; throws InputError/Error for bad input.
int run_gcode_correction(const GcodeCorrectionCliOptions& o);

}  // namespace mtcal::cli
