// Pieces shared by the mtcal commands: model options (--machine, --params, --set, --only ...).
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "mtcal/evaluation/motion_program.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/model/machine.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {

struct ModelOptions {
  std::string machine;
  std::vector<std::string> params;
  std::vector<std::string> set;
  std::string only;
  std::optional<double> tool_length;
};

void add_model_options(CLI::App* cmd, ModelOptions& o);
// The machine with --params, --tool-length, --only and --set applied, in that order.
Machine load(const ModelOptions& o);

// Refuses (InputError) an output path that is one of the inputs or another output, before any
// work: a report must never replace the measurements it reports on.
void check_outputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);
// The model options' files (machine, parameter files), for check_outputs and report inputs.
std::vector<std::string> model_inputs(const ModelOptions& o);
// CLI11 check: a finite number (CLI11's Range lets NaN through).
extern const CLI::Validator kFinite;
// CLI11 check: a unit name of a length or an angle (mm, um, in, deg, arcsec ...; no slopes).
extern const CLI::Validator kUnitName;
// Adds the finite-number check to every FLOAT option of app and of its commands that has no
// FINITE check of its own: CLI11 reads 'nan' and 'inf' as numbers, and its Range lets NaN through.
void require_finite_numbers(CLI::App& app);
// CLI11 transforms for a length or angle option: a value with a unit suffix ("150mm", "0.5um",
// "6in"; "90deg", "20urad") is rewritten as a bare number in the option's own unit (mm_per_unit:
// mm per that unit, 1 for mm, 1e-3 for um); a bare number stays as it is. Errors list the units.
CLI::Validator length_in(double mm_per_unit, const char* unit_name);
CLI::Validator angle_in(double rad_per_unit, const char* unit_name);

// "mtcal: warning: MESSAGE" on stderr: a value that is accepted but probably not meant.
void warn(const std::string& message);

// The grid of option --grid (parse_grid), refused beyond max_count configurations and with its
// corners checked against the travels (check_grid); errors located in "--grid".
std::vector<std::vector<double>> checked_grid(const Machine& m, const std::string& spec, bool travel_check,
                                              std::size_t max_count = 4'000'000'000);

// Called in a catch block of an InputError: when the library located it in one of its parameters
// (names[i].first, e.g. "step"), rethrows it located in the option that gave the value
// (names[i].second, e.g. "--step"), message unchanged; a RequestError located in the data whose
// causes are among those parameters gets the options added, "... (--step, --angle-step)";
// otherwise rethrows it as it is.
[[noreturn]] void rethrow_for_options(const InputError& e,
                                      const std::vector<std::pair<std::string, std::string>>& names);

// "X=100,Z=-450" (option --origin) -> program zero in machine axis positions (mm, deg), like a G54
// offset; letters of the machine only, each once. Errors are located in "--origin".
GcodePosition parse_program_origin(const Machine& m, const std::string& spec);

// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& s);

// The command line as typed (arguments with spaces or quotes are quoted), for reports.
void set_command_line(int argc, char** argv);
const std::string& command_line();

// A subcommand and what running it does (its options live in the closure).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// Probing commands: rotary-axis, probe-sim (cmd_probing.cpp).
std::vector<Command> add_probing_commands(CLI::App& app);
// Acceptance-test evaluations: iso230-2 (cmd_evaluation.cpp).
std::vector<Command> add_evaluation_commands(CLI::App& app);
// Measurements to model parameters: fit-motion (cmd_fit_motion.cpp).
std::vector<Command> add_fit_motion_commands(CLI::App& app);
// Method comparison: compare (cmd_compare.cpp).
std::vector<Command> add_compare_commands(CLI::App& app);
// Volumetric accuracy: volumetric, contributions, diagonals (cmd_volumetric.cpp).
std::vector<Command> add_volumetric_commands(CLI::App& app);
// Tool-path simulation from G-code: toolpath (cmd_toolpath.cpp).
std::vector<Command> add_toolpath_commands(CLI::App& app);
// Identification from probing: simulate, identify, identifiability (cmd_identification.cpp).
std::vector<Command> add_identification_commands(CLI::App& app);
// Compensation: compensate (cmd_compensation.cpp; its --gcode part in cmd_gcode_correction.cpp).
std::vector<Command> add_compensation_commands(CLI::App& app);
// Workpiece error prediction (Yaqoob 2017): regress, predict, separate (cmd_prediction.cpp).
std::vector<Command> add_prediction_commands(CLI::App& app);
// A calibration campaign judged: pose-check, campaign (cmd_campaign.cpp).
std::vector<Command> add_campaign_commands(CLI::App& app);
// History analyses: diff, trend, rank, as subcommands of `history` (cmd_history_analysis.cpp).
std::vector<Command> add_history_analysis_commands(CLI::App& history);

}  // namespace mtcal::cli
