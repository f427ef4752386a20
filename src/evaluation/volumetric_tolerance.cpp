#include "mtcal/evaluation/volumetric_tolerance.hpp"

namespace mtcal {

std::vector<std::pair<std::string, double>> tolerance_values(const VolumetricAccuracy& va) {
  const auto& c = va.component;
  return {{"VA", va.va.value * 1e3}, {"VAx", c[0].value * 1e3}, {"VAy", c[1].value * 1e3}, {"VAz", c[2].value * 1e3}};
}

}  // namespace mtcal
