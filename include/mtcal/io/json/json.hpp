// JSON of mtcal's results: the common pieces every per-module serialiser (io/*_json.hpp) builds on.
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// Keys keep the order they are written in: the documented output order of every --json.
using Json = nlohmann::ordered_json;

// The text of j (indent < 0: one line). JSON is UTF-8 (RFC 8259, section 8.1), and file names
// and texts from files need not be: every byte of a string that is not part of a valid UTF-8
// sequence (a file name written in Latin-1, a header from Windows software) is written as
// U+FFFD, the replacement character, as the HTML reports do and as Unicode's "substitution of
// maximal subparts" recommends (docs/reliability.md, "Text in JSON"). Never throws for text.
std::string json_text(const Json& j, int indent = -1);
std::string json_text(const nlohmann::json& j, int indent = -1);
// text with the same replacement: what json_text writes of it (a history record holds that).
std::string utf8_text(std::string_view text);
// Whether text is valid UTF-8 (no byte json_text would replace).
bool is_utf8(std::string_view text);

// {"X": 100, "B": 30}: a configuration (internal units, chain order) in user units (mm, deg).
Json joint_json(const Machine& m, std::span<const double> q);

// [x, y, z]
inline Json vec3_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

// A number, or null where it is absent or not finite (JSON has no NaN or infinity).
inline Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }
inline Json number_or_null(const std::optional<double>& v) { return v ? number_or_null(*v) : Json(nullptr); }

}  // namespace mtcal
