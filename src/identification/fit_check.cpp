#include "mtcal/identification/fit_check.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

FitCheck check_fit(const IdentificationResult& r, double probability) {
  if (!(probability > 0.5 && probability < 1.0))
    throw InputError({"fit probability", 0, ""}, fmt::format("expected 0.5 < p < 1, found {:g}", probability));
  FitCheck f;
  f.sigma0 = r.sigma0;
  f.probability = probability;
  f.rms_ball = r.rms_ball;
  f.rms_facet = r.rms_facet;
  f.rms_scale_bar = r.rms_scale_bar;
  f.degrees_of_freedom = r.residuals > r.unknowns ? r.residuals - r.unknowns : 0;
  if (f.degrees_of_freedom == 0) {
    f.bound = std::numeric_limits<double>::infinity();
    return f;
  }
  // z: the standard normal quantile, Phi(z) = (1/2) erfc(-z / sqrt 2) = probability, by bisection.
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < probability ? lo : hi) = mid;
  }
  const double z = 0.5 * (lo + hi), k = static_cast<double>(f.degrees_of_freedom);
  const double c = 1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k));
  f.bound = std::sqrt(c * c * c);  // sqrt(chi2_p(k) / k)
  f.poor = !(r.sigma0 <= f.bound);
  return f;
}

std::string describe_fit(const FitCheck& f) {
  return fmt::format("sigma0 {:.3g} against the bound {:.3g} ({:g} % of correct fits stay below it, {} degrees of "
                     "freedom); residual rms: balls {:.3f} um, facets {:.3f} um, scale bars {:.3f} um",
                     f.sigma0, f.bound, f.probability * 100, f.degrees_of_freedom, f.rms_ball * 1e3,
                     f.rms_facet * 1e3, f.rms_scale_bar * 1e3);
}

std::string poor_fit_message(const FitCheck& f) {
  return "the fit is poor: " + describe_fit(f) +
         ". The residuals are larger than the readings' sigma explains: errors the estimate cannot absorb, "
         "measurements that do not belong to the plan, or a sigma too small";
}

}  // namespace mtcal
