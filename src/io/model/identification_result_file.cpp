#include "mtcal/io/model/identification_result_file.hpp"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// Ordered: the parameters keep identify's order.
using json = nlohmann::ordered_json;

const json& member(const json& j, const char* key, const std::string& source, const std::string& path) {
  if (!j.is_object() || !j.contains(key))
    throw InputError({source, 0, path + key}, std::string("expected the key '") + key +
                                                  "' of identify --json output, found none");
  return j.at(key);
}

double number(const json& j, const std::string& source, const std::string& key, bool null_is_nan = false) {
  if (null_is_nan && j.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!j.is_number() || !std::isfinite(j.get<double>()))
    throw InputError({source, 0, key}, "expected a finite number, found " + printable(j.dump()));
  return j.get<double>();
}

}  // namespace

IdentifiedSummary parse_identification_json(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError({source, 0, ""}, std::string("expected the JSON of identify --json, found text that is not JSON (") +
                                          e.what() + ")");
  }
  IdentifiedSummary s;
  s.source = source;
  const json& conv = member(j, "converged", source, "");
  if (!conv.is_boolean()) throw InputError({source, 0, "converged"}, "expected true or false, found " + printable(conv.dump()));
  s.converged = conv.get<bool>();
  for (const auto& [key, slot] : {std::pair{"residuals", &s.residuals}, {"unknowns", &s.unknowns}, {"rank", &s.rank}}) {
    const json& v = member(j, key, source, "");
    if (!v.is_number_unsigned()) throw InputError({source, 0, key}, "expected a count, found " + printable(v.dump()));
    *slot = v.get<std::size_t>();
  }
  const json& rms = member(j, "rms_um", source, "");
  s.rms_ball = number(member(rms, "ball", source, "rms_um."), source, "rms_um.ball") * 1e-3;
  s.rms_facet = number(member(rms, "facet", source, "rms_um."), source, "rms_um.facet") * 1e-3;
  s.sigma0 = number(member(j, "sigma0", source, ""), source, "sigma0");
  const json& params = member(j, "parameters", source, "");
  if (!params.is_object()) throw InputError({source, 0, "parameters"}, "expected an object of parameters by name");
  for (const auto& [name, p] : params.items()) {
    EstimatedParameter e;
    e.name = name;
    const std::string at = "parameters." + name + ".";
    e.value = number(member(p, "value", source, at), source, at + "value");
    e.u = number(member(p, "u", source, at), source, at + "u", true);
    const json& unit = member(p, "unit", source, at);
    if (!unit.is_string()) throw InputError({source, 0, at + "unit"}, "expected a unit name, found " + printable(unit.dump()));
    e.unit = unit.get<std::string>();
    s.parameters.push_back(e);
  }
  if (j.contains("unidentifiable") && j["unidentifiable"].is_array())
    for (const auto& u : j["unidentifiable"])
      if (u.is_string()) s.unidentifiable.push_back(u.get<std::string>());
  if (j.contains("artefact") && j["artefact"].is_object() && j["artefact"].contains("balls")) {
    const json& balls = j["artefact"]["balls"];
    if (!balls.is_object()) throw InputError({source, 0, "artefact.balls"}, "expected an object of ball centres by id");
    for (const auto& [id, c] : balls.items()) {
      const std::string at = "artefact.balls." + id;
      if (!c.is_array() || c.size() != 3) throw InputError({source, 0, at}, "expected [x, y, z], found " + printable(c.dump()));
      s.balls[id] = Vec3(number(c[0], source, at), number(c[1], source, at), number(c[2], source, at));
    }
  }
  return s;
}

IdentifiedSummary read_identification_json(const std::string& path) {
  return parse_identification_json(read_text_file(path, "identification JSON"), path);
}

}  // namespace mtcal
