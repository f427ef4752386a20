// JSON of the error-model evaluations: the volumetric error at a configuration, a streamed evaluation's summary, the
// error parameters, single-error effects.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// {"dx", "dy", "dz" (mm), "rx", "ry", "rz" (rad)}
Json to_json(const VolumetricError& e);

// {"configurations", "seconds", "max_translation": {"value" (mm), "at"}, "max_rotation": {"value"
// (rad), "at"}}; "at" is {} when there was no configuration.
Json to_json(const Machine& m, const StreamSummary& s);

// {"machine", "topology", "parameters": [{"name", "error", "kind", "unit", "value"}]}
Json to_json(const Machine& m, std::span<const ErrorParameter> parameters);

// {"machine", "topology", "at", "tool_length", "around", "effects": [{"error", "kind", "per", "dx" ..
// "rz"}]}: effects per 1 um or 1 urad ("per"), dx dy dz in um, rx ry rz in urad.
Json to_json(const Machine& m, std::span<const double> at, const std::string& around,
             std::span<const ErrorEffect> effects);

}  // namespace mtcal
