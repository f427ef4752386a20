#include "mtcal/io/json/error_map_json.hpp"

#include "mtcal/io/text/error_keys.hpp"

namespace mtcal {

Json to_json(const VolumetricError& e) {
  const double v[6] = {e.translation.x(), e.translation.y(), e.translation.z(),
                       e.rotation.x(),    e.rotation.y(),    e.rotation.z()};
  Json j;
  for (int c = 0; c < 6; ++c) j[kErrorKeys[c]] = v[c];
  return j;
}

Json to_json(const Machine& m, const StreamSummary& s) {
  Json j;
  j["configurations"] = s.count;
  j["seconds"] = s.seconds;
  auto at = [&](const ErrorExtreme& x) { return s.count ? joint_json(m, x.at) : Json::object(); };
  j["max_translation"] = {{"value", s.max_translation.value}, {"at", at(s.max_translation)}};
  j["max_rotation"] = {{"value", s.max_rotation.value}, {"at", at(s.max_rotation)}};
  return j;
}

Json to_json(const Machine& m, std::span<const ErrorParameter> parameters) {
  Json arr = Json::array();
  for (const auto& p : parameters)
    arr.push_back({{"name", p.name},
                   {"error", p.error.str()},
                   {"kind", std::string(to_string(p.error.kind))},
                   {"unit", p.unit},
                   {"value", p.value}});
  Json j;
  j["machine"] = m.name;
  j["topology"] = m.topology.chain;
  j["parameters"] = arr;
  return j;
}

Json to_json(const Machine& m, std::span<const double> at, const std::string& around,
             std::span<const ErrorEffect> effects) {
  Json arr = Json::array();
  for (const auto& e : effects) {
    Json j{{"error", e.error.str()},
           {"kind", std::string(to_string(e.error.kind))},
           {"per", e.rotational ? "urad" : "um"}};
    for (int c = 0; c < 6; ++c) j[kErrorKeys[c]] = e.effect[static_cast<std::size_t>(c)];
    arr.push_back(j);
  }
  Json j;
  j["machine"] = m.name;
  j["topology"] = m.topology.chain;
  j["at"] = joint_json(m, at);
  j["tool_length"] = m.tool.length;
  j["around"] = around;
  j["effects"] = arr;
  return j;
}

}  // namespace mtcal
