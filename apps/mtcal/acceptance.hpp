// Acceptance-report options shared by the commands: --meta, --meta-file, --tolerance,
// --tolerance-file, --fail-on-tolerance; JSON output with the run's metadata.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/evaluation/metadata.hpp"

namespace mtcal::cli {

// Adds --meta and --meta-file to every command that has --report or --json.
void add_metadata_options(CLI::App& app);
// Reads --meta-file, applies --meta over it and makes the result the session's metadata
// (set_session_metadata). Called once before a command runs.
void load_session_metadata();
// The files --meta-file names (for check_outputs).
std::vector<std::string> metadata_inputs();
// When the run is an acceptance test (a report, tolerances or metadata were asked for), one
// warning line on stderr per field the test's report should state and lacks.
void warn_missing_metadata(AcceptanceTest test, bool acceptance_run);

// Adds --report-pdf FILE and --report-png DIR to every command that has --report.
void add_static_copy_options(CLI::App& app);
// For the parsed command cmd: refuses them without --report, or with the report's own path, and
// finds the browser before any work (a one-line error naming the missing program); then sets the
// reports' static copies (set_static_copies).
void load_static_copies(CLI::App& cmd);

// Prints j (2-space indent) with the session's metadata under "metadata" when there is any.
void print_json(Json j);

struct ToleranceOptions {
  std::vector<std::string> limits;  // "A=8", "VA=0.03mm"
  std::string file;
  bool fail_exit = false;
  bool given() const { return !limits.empty() || !file.empty(); }
};
// quantities: the quantities this command gives, for --help (e.g. "A, E, M, R, B").
void add_tolerance_options(CLI::App* cmd, ToleranceOptions& o, const std::string& quantities);
// The limits for this test: the file's section (ISO 230-2: the axis' entry, else "any"), then
// each --tolerance over it. Values in µm; --tolerance takes a um, µm or mm suffix.
Tolerances tolerances_for(const ToleranceOptions& o, AcceptanceTest test, const std::string& axis = "");
// Checks, with errors located in the tolerance options.
ToleranceVerdict checked_verdict(const std::vector<std::pair<std::string, double>>& values, const Tolerances& t);
// "PASS: A 5.2 <= 8 um, ..." lines on stdout (nothing for an empty verdict).
void print_verdict(const ToleranceVerdict& v);
// 0, or 3 when the verdict failed and --fail-on-tolerance was given: a verdict is a result, not
// an error.
int verdict_exit_code(const ToleranceOptions& o, const ToleranceVerdict& v);

}  // namespace mtcal::cli
