// JSON of the acceptance records: report metadata and the tolerance verdict (io/json/acceptance_json.hpp).
#include "mtcal/io/json/acceptance_json.hpp"

namespace mtcal {

Json to_json(const ReportMetadata& m) {
  Json j = Json::object();
  for (const auto& [k, v] : m.entries()) j[k] = v;
  return j;
}

Json to_json(const ToleranceVerdict& v) {
  Json checks = Json::array();
  for (const auto& c : v.checks)
    checks.push_back({{"quantity", c.quantity}, {"value", c.value}, {"limit", c.limit}, {"pass", c.pass}});
  return {{"verdict", v.pass() ? "pass" : "fail"}, {"unit", "um"}, {"checks", checks}};
}

}  // namespace mtcal
