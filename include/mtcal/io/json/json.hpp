// JSON of mtcal's results: the common pieces every per-module serialiser (io/*_json.hpp) builds on.
#pragma once

#include <cmath>
#include <optional>
#include <span>

#include <nlohmann/json.hpp>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// Keys keep the order they are written in: the documented output order of every --json.
using Json = nlohmann::ordered_json;

// {"X": 100, "B": 30}: a configuration (internal units, chain order) in user units (mm, deg).
Json joint_json(const Machine& m, std::span<const double> q);

// [x, y, z]
inline Json vec3_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

// A number, or null where it is absent or not finite (JSON has no NaN or infinity).
inline Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }
inline Json number_or_null(const std::optional<double>& v) { return v ? number_or_null(*v) : Json(nullptr); }

}  // namespace mtcal
