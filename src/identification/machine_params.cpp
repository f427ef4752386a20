// Measured errors as model parameters (identification/machine_params.hpp).
#include "mtcal/identification/machine_params.hpp"

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

void check_distinct(const std::vector<EstimatedError>& errors) {
  for (std::size_t i = 0; i < errors.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (errors[i].name == errors[j].name)
        throw InputError({errors[i].source, 0, errors[i].name.str()},
                         fmt::format("{} is estimated twice: from {} and from {} (give each error once)",
                                     errors[i].name.str(), errors[j].source, errors[i].source));
}

std::vector<EstimatedError> ballbar_parameters(const TraceDiagnosis& d, const std::string& plane,
                                               const BallbarParamsOptions& o, const std::string& source) {
  if (plane != "XY" && plane != "YZ" && plane != "ZX")
    throw InputError({source, 0, "plane"}, "expected the plane XY, YZ or ZX, found '" + plane + "'");
  const std::string a1(1, plane[0]), a2(1, plane[1]);
  auto term = [&](const std::string& name) -> const TraceTerm& {
    for (const auto& t : d.terms)
      if (t.name == name) return t;
    throw InputError({source, 0, name}, "the diagnosis has no term '" + name + "'");
  };
  std::vector<EstimatedError> out;
  if (o.squareness) {
    // Radial deviation of a squareness s: -(R/2) s sin 2a (ballbar.cpp's model column). The
    // second axis's orientation error moves the first axis's coordinate by -EC0Y * y (XY),
    // -EA0Z * z (YZ: y moves by -EA0Z z), and in ZX x moves by +EB0Z * z (conventions.md:
    // right-hand rotations), so EB0Z takes the opposite sign.
    const TraceTerm& t = term("squareness " + a1 + a2);
    const char* name = plane == "XY" ? "EC0Y" : plane == "YZ" ? "EA0Z" : "EB0Z";
    const double sign = plane == "ZX" ? -1.0 : 1.0;
    EstimatedError e;
    e.name = *ErrorName::parse(name);
    e.value = sign * t.value * 1e-6;
    e.uncertainty = {t.uncertainty * 1e-6};
    e.source = source;
    e.method = fmt::format("ballbar squareness {}: {:.3f} +- {:.3f} um/m", a1 + a2, t.value, t.uncertainty);
    out.push_back(e);
  }
  if (o.scale || o.backlash) {
    const TraceTerm& mismatch = term("scaling mismatch " + a1 + a2);
    for (int k = 0; k < 2; ++k) {
      const std::string& axis = k == 0 ? a1 : a2;
      Polynomial p;
      std::vector<double> u(5, 0.0);
      std::string method;
      if (o.scale) {
        // (R/2) m cos 2a with m = slope1 - slope2; half to each axis.
        p.coefficients[1] = (k == 0 ? 0.5 : -0.5) * mismatch.value * 1e-6;
        u[1] = 0.5 * mismatch.uncertainty * 1e-6;
        method += fmt::format("ballbar scaling mismatch {}: {:.3f} +- {:.3f} um/m, {} half", a1 + a2, mismatch.value,
                              mismatch.uncertainty, k == 0 ? "+" : "-");
      }
      if (o.backlash) {
        const TraceTerm& b = term("backlash " + axis);
        p.reversal = -0.5 * b.value * 1e-3;
        u[4] = 0.5 * b.uncertainty * 1e-3;
        method += fmt::format("{}ballbar backlash {}: {:.3f} +- {:.3f} um", method.empty() ? "" : "; ", axis, b.value,
                              b.uncertainty);
      }
      EstimatedError e;
      e.name = *ErrorName::parse("E" + axis + axis);
      e.motion = MotionFunction(p);
      e.uncertainty = u;
      e.source = source;
      e.method = method;
      out.push_back(e);
    }
  }
  return out;
}

}  // namespace mtcal
