// Why removing an error and its first-order share disagree: the errors it cancels at the pair that becomes critical.
#pragma once

#include <algorithm>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"

namespace mtcal::detail {

// `there`: the full machine's contributions at the pair that is critical without w.error. Sets
// w.along_there, and w.cancelled to the errors whose effects there oppose w.error's own (same
// component, opposite sign: e.g. a squareness against the straightness along the same axis),
// largest first. Shared by the in-memory and the streamed volumetric studies.
inline void explain_disagreement(WhatIf& w, const ContributionAnalysis& there) {
  Vec3 own = Vec3::Zero();
  for (const auto& c : there.items)
    if (c.error == w.error) w.along_there = c.along, own = c.effect;
  if (own.norm() > 0)
    for (const auto& c : there.items) {
      const double against = -c.effect.dot(own) / own.norm();
      if (c.error != w.error && against > 0) w.cancelled.emplace_back(c.error, against);
    }
  std::stable_sort(w.cancelled.begin(), w.cancelled.end(),
                   [](const auto& x, const auto& y) { return x.second > y.second; });
}

}  // namespace mtcal::detail
