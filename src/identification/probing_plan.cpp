#include "mtcal/identification/probing_plan.hpp"

#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

std::optional<std::size_t> ProbingPlan::feature_index(const std::string& id) const {
  for (std::size_t i = 0; i < features.size(); ++i)
    if (features[i].id == id) return i;
  return std::nullopt;
}

std::size_t ProbingPlan::residual_count() const {
  std::size_t n = 0;
  for (const auto& r : records) n += readings_of(features[r.feature].kind);
  return n;
}

const char* feature_kind_name(ProbeFeature::Kind kind) {
  switch (kind) {
    case ProbeFeature::Kind::Ball: return "ball";
    case ProbeFeature::Kind::Facet: return "facet";
    case ProbeFeature::Kind::Ballbar: return "ballbar";
    case ProbeFeature::Kind::Laser: return "laser";
  }
  return "?";
}

int ballbar_plane(const ProbeFeature& f) {
  for (int k = 0; k < 3; ++k)
    if (f.normal.isApprox(Vec3::Unit(k), 1e-9)) return k;
  throw InputError({"feature", 0, f.id},
                   fmt::format("expected a ballbar plane XY, YZ or ZX (normal +z, +x or +y), found normal {:g} {:g} {:g}",
                               f.normal.x(), f.normal.y(), f.normal.z()));
}

Vec3 instrument_target(const ProbeFeature& f, double at) {
  if (f.kind == ProbeFeature::Kind::Laser) return f.position + at * f.normal;
  if (f.kind != ProbeFeature::Kind::Ballbar)
    throw InputError({"feature", 0, f.id}, "expected a ballbar or a laser feature");
  // ISO 230-4's planes: XY, YZ, ZX, each angle from the first axis towards the second.
  const int k = ballbar_plane(f);
  const Vec3 e1 = Vec3::Unit((k + 1) % 3), e2 = Vec3::Unit((k + 2) % 3);
  return f.position + f.radius * (std::cos(at) * e1 + std::sin(at) * e2);
}

}  // namespace mtcal
