// Whether an identification's residuals are what the readings' sigma explains (a poor fit is named, not used).
#pragma once

#include <cstddef>
#include <string>

#include "mtcal/identification/identification.hpp"

namespace mtcal {

// With the model reaching the measurements and the sigma right, sigma0^2 (m - n) is chi-square with
// m - n degrees of freedom (Gauss-Markov: the weighted sum of squared residuals of a linear(ised)
// least-squares fit). Its upper quantile by Wilson & Hilferty's cube-root approximation (1931):
// k (1 - 2/(9k) + z sqrt(2/(9k)))^3, z the standard normal quantile. A sigma0 above the bound says
// the fit is poor: errors the estimate cannot absorb (a truth outside the model's reach), a log that
// does not belong to the plan, or a sigma too small — in every case the identified values are not to
// be used as they are.
struct FitCheck {
  bool poor = false;
  double sigma0 = 0.0;
  double bound = 0.0;        // largest sigma0 at the probability (infinite without degrees of freedom)
  double probability = 0.0;  // of a correct model staying below the bound
  std::size_t degrees_of_freedom = 0;
  double rms_ball = 0.0, rms_facet = 0.0, rms_scale_bar = 0.0;  // mm, as the result has them
};

// Throws InputError for a probability outside (0.5, 1).
FitCheck check_fit(const IdentificationResult& result, double probability = 0.999);

// The check in words: "sigma0 S against the bound B (P % of correct fits stay below it, K degrees
// of freedom); residual rms: balls .. um, facets .. um, scale bars .. um".
std::string describe_fit(const FitCheck& f);
// What a poor fit means, for a warning or a refusal: "the fit is poor: <describe_fit>. The
// residuals are larger than the readings' sigma explains: ...".
std::string poor_fit_message(const FitCheck& f);

}  // namespace mtcal
