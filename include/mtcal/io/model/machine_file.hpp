// Reading and writing machine files (YAML, specified in docs/machine-file.md).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// Loads a machine completely or throws InputError naming file, line and key.
Machine load_machine(const std::string& path);
// Same from text; source names the text in messages.
Machine parse_machine(std::string_view yaml_text, const std::string& source);
// Parameter files: `mtcal_parameters: 1`, optional `units`, and an `errors` section written as
// in a machine file; each error given replaces the machine's. All or nothing; InputError with
// file, line and key otherwise.
void load_parameters(Machine& m, const std::string& path);
void apply_parameters(Machine& m, std::string_view yaml_text, const std::string& source);
// A parameter file's text in either form load_parameters reads: an Etalon exchange file (what
// --format etalon writes; apply_etalon) or the YAML above (apply_parameters).
void apply_parameter_file(Machine& m, std::string_view text, const std::string& source);

// YAML text that parse_machine reads back to the same machine (internal units, full precision).
std::string to_yaml(const Machine& m);
// A parameter file (load_parameters reads it) with these errors' values in m, internal units,
// full precision; comment lines (split at newlines) first.
std::string parameters_yaml(const Machine& m, const std::vector<ErrorName>& errors, const std::string& comment = "");
// One error's entry of an `errors:` section as written by to_yaml.
std::string error_yaml(const Machine& m, const ErrorName& error);

}  // namespace mtcal
