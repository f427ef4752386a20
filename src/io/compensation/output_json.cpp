#include "mtcal/io/compensation/output_json.hpp"

namespace mtcal {

Json to_json(const TargetOutput& output) {
  const CompensationSummary& s = output.summary;
  Json j;
  j["target"] = s.target;
  j["quantity"] = to_string(s.quantity);
  j["sign_source"] = s.sign_source;
  Json files = Json::array();
  for (const auto& f : output.files) files.push_back(f.name);
  j["files"] = files;
  Json left = Json::array();
  for (const auto& n : s.not_compensated)
    left.push_back({{"what", n.what}, {"max_error", n.max_error}, {"unit", n.unit}});
  j["not_compensated"] = left;
  j["warnings"] = s.warnings;
  const ResidualSummary& r = s.residual;
  j["residual"] = {{"configurations", r.configurations},
                   {"max_before_mm", r.max_before},
                   {"max_after_mm", r.max_after},
                   {"max_norm_before_mm", r.max_norm_before},
                   {"max_norm_after_mm", r.max_norm_after},
                   {"va_before_mm", r.va_before},
                   {"va_after_mm", r.va_after}};
  Json commanded = Json::array();
  for (const auto& c : s.commanded)
    commanded.push_back({{"axis", std::string(1, c.axis)},
                         {"lo", c.lo},
                         {"hi", c.hi},
                         {"unit", c.unit},
                         {"given", c.given},
                         {"margin", c.margin},
                         {"largest_correction", c.largest_correction},
                         {"why", c.why}});
  j["commanded_range"] = commanded;
  return j;
}

}  // namespace mtcal
