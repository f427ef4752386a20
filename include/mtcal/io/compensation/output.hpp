// Compensation output as files: what every target writes into its output directory, all or nothing
// (its JSON summary: io/compensation/output_json.hpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One file of a target, its name relative to the output directory (no '/').
struct TargetFile {
  std::string name;
  std::string text;
};

// A target's files (the tables and the snippet that loads them: INI, HAL, config lines) and its summary.
struct TargetOutput {
  std::vector<TargetFile> files;
  CompensationSummary summary;
};

// A compensation target as `--format` names it.
struct CompensationTarget {
  std::string name;         // "linuxcnc"
  std::string description;  // one line for --help
  std::function<TargetOutput(const Machine&, const CompensationOptions&)> run;
};

// Every target mtcal writes, in --format order.
const std::vector<CompensationTarget>& compensation_targets();
// The target named `name`; throws InputError (field "format") listing the known ones.
const CompensationTarget& compensation_target(const std::string& name);

// Writes the files into `dir`, which must not exist yet or be an empty directory: they are
// written into a temporary sibling directory that is renamed to `dir` at the end, so `dir`
// holds every file or none. Throws Error naming the path that failed.
void write_target_output(const std::string& dir, const TargetOutput& output);

}  // namespace mtcal
