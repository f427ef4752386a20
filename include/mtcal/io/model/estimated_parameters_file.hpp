// Parameter files of estimated errors (fit-motion, ballbar --to-params): values, uncertainties and provenance.
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/machine_params.hpp"

namespace mtcal {

// A parameter file (docs/machine-file.md, "Parameter files") that load_parameters reads: every
// error in internal units (mm, rad) at full precision, each with a comment saying where it came
// from, how, and the standard uncertainty of each parameter. description: the first comment.
std::string estimated_parameters_yaml(const std::vector<EstimatedError>& errors, const std::string& description);
void write_estimated_parameters(const std::string& path, const std::vector<EstimatedError>& errors,
                                const std::string& description);

}  // namespace mtcal
