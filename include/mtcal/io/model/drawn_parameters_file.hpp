// Parameter files of a drawn truth (errors --draw): the truth's errors and the nominal model they are drawn on.
#pragma once

#include <string>

#include "mtcal/identification/error_draw.hpp"

namespace mtcal {

// A parameter file with every error of the machine (zero ones too), its values: applied with
// --params to a machine of the same axes it gives exactly these errors.
std::string every_error_yaml(const Machine& m, const std::string& comment);

// A parameter file (load_parameters reads it) with every error of the machine: the truth's drawn
// values, every other error zero, so that `--params FILE` on the machine the draw started from
// (whatever errors its file holds) gives exactly the truth. The comment names the seed, the
// sizes and each drawn error; description is its first line.
std::string truth_parameters_yaml(const ErrorDraw& draw, const std::string& description);
// The same errors with the same forms (drawn tables as tables at their positions), every value
// zero: the model a calibration of the truth estimates, without the truth's values.
std::string nominal_parameters_yaml(const ErrorDraw& draw, const std::string& description);
void write_truth_parameters(const std::string& path, const ErrorDraw& draw, const std::string& description);
void write_nominal_parameters(const std::string& path, const ErrorDraw& draw, const std::string& description);

}  // namespace mtcal
