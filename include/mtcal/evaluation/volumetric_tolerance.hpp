// The quantities a volumetric acceptance is judged by: VA and its components, in µm, for check_tolerances.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mtcal/evaluation/volumetric.hpp"

namespace mtcal {

// VA, VAx, VAy, VAz in µm (Mohammed 2019's volumetric accuracy, docs/volumetric.md), from the
// exact VA of a map (mm), in that order: the quantities of a tolerance file's volumetric section.
std::vector<std::pair<std::string, double>> tolerance_values(const VolumetricAccuracy& va);

}  // namespace mtcal
