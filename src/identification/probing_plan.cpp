#include "mtcal/identification/probing_plan.hpp"

namespace mtcal {

std::optional<std::size_t> ProbingPlan::feature_index(const std::string& id) const {
  for (std::size_t i = 0; i < features.size(); ++i)
    if (features[i].id == id) return i;
  return std::nullopt;
}

std::size_t ProbingPlan::residual_count() const {
  std::size_t n = 0;
  for (const auto& r : records) n += features[r.feature].kind == ProbeFeature::Kind::Ball ? 3 : 1;
  return n;
}

}  // namespace mtcal
