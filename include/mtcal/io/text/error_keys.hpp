// Stable names of a volumetric error's components: the CSV columns and the JSON keys mtcal writes.
#pragma once

namespace mtcal {

// dx dy dz (mm), rx ry rz (rad): the order of the error model's six components (docs/conventions.md).
inline constexpr const char* kErrorKeys[6] = {"dx", "dy", "dz", "rx", "ry", "rz"};

}  // namespace mtcal
