// Pieces shared by the mtcal commands: model options (--machine, --params, --set, --only ...).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mtcal/model/machine.hpp"

namespace mtcal::cli {

// Stable JSON keys and CSV columns of a volumetric error.
inline constexpr const char* kOutputKeys[6] = {"dx", "dy", "dz", "rx", "ry", "rz"};

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
// Method comparison: compare (cmd_compare.cpp).
std::vector<Command> add_compare_commands(CLI::App& app);
// Volumetric accuracy: volumetric, contributions, diagonals (cmd_volumetric.cpp).
std::vector<Command> add_volumetric_commands(CLI::App& app);
// Tool-path simulation from G-code: toolpath (cmd_toolpath.cpp).
std::vector<Command> add_toolpath_commands(CLI::App& app);

}  // namespace mtcal::cli
