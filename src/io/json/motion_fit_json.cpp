#include "mtcal/io/json/motion_fit_json.hpp"

namespace mtcal {

Json to_json(const EstimatedError& e, const MotionFit& f) {
  Json params = Json::object();
  if (e.motion)
    for (std::size_t k = 0; k < e.motion->parameter_count(); ++k)
      params[e.name.str() + "." + e.motion->parameter_suffix(k)] = {
          {"value", e.motion->parameter(k)}, {"u", k < e.uncertainty.size() ? Json(e.uncertainty[k]) : Json(nullptr)}};
  return {{"error", e.name.str()},
          {"file", e.source},
          {"form", f.form},
          {"degree", f.degree},
          {"targets", f.targets},
          {"bidirectional", f.bidirectional},
          {"residual_rms", f.residual_rms},
          {"u_mean", f.u_mean},
          {"reason", f.reason},
          {"notes", f.notes},
          {"parameters", params}};
}

Json motion_fits_json(const std::vector<EstimatedError>& errors, const std::vector<MotionFit>& fits,
                      const std::vector<std::string>& warnings, const std::string& out) {
  Json j;
  Json list = Json::array();
  for (std::size_t i = 0; i < errors.size() && i < fits.size(); ++i) list.push_back(to_json(errors[i], fits[i]));
  j["errors"] = list;
  j["units"] = "internal: mm and rad";
  j["warnings"] = warnings;
  if (!out.empty()) j["out"] = out;
  return j;
}

}  // namespace mtcal
