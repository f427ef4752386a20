// The parameter file of an identification (identify --out): the identified errors, readable by load_parameters.
#pragma once

#include <string>

#include "mtcal/identification/identification.hpp"

namespace mtcal {

// A parameter file with the errors whose parameters were estimated (identified_errors), their
// values in result.machine, and a comment: what was identified from measurements_source
// (residuals, unknowns, rank, rms), each estimate with its standard uncertainty, and what was
// not identifiable.
std::string identified_parameters_yaml(const Machine& prior, const IdentificationResult& result,
                                       const std::string& measurements_source);
void write_identified_parameters(const std::string& path, const Machine& prior, const IdentificationResult& result,
                                 const std::string& measurements_source);

}  // namespace mtcal
