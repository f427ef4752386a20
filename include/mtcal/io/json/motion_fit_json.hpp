// JSON of fitted motion errors (mtcal fit-motion --json, docs/fit-motion.md).
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/machine_params.hpp"
#include "mtcal/identification/motion_fit.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// One fitted error: error file form degree targets bidirectional residual_rms u_mean reason notes
// parameters {NAME.suffix: {value, u}} (every coefficient, internal units mm, rad).
Json to_json(const EstimatedError& e, const MotionFit& f);
// errors[] (as above, errors[i] with fits[i]), units, warnings, [out] (the parameter file written,
// when not empty).
Json motion_fits_json(const std::vector<EstimatedError>& errors, const std::vector<MotionFit>& fits,
                      const std::vector<std::string>& warnings, const std::string& out = "");

}  // namespace mtcal
