// JSON of the rotary-axis location test (probing): both estimates, the triples' histograms, the centres.
#pragma once

#include <array>
#include <string>

#include "mtcal/io/json/json.hpp"
#include "mtcal/probing/rotary_probing.hpp"

namespace mtcal {

// One estimate: per quantity its value, "_u" uncertainty (null unless u_known) and "_spread";
// axis_point, axis_direction.
Json to_json(const RotaryEstimate& e, const std::array<std::string, kRotaryQuantities>& names, bool u_known);

// axis, indexations, centre_method, units, triples, least_squares, centres[]
// (docs/rotary-axis.md, "JSON keys").
Json to_json(const RotaryAxisResult& r);

}  // namespace mtcal
