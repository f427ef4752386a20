#include "brute_force.hpp"

#include <cmath>

namespace mtcal::testing {

BruteForceVa brute_force_va(std::span<const Eigen::Vector3d> e) {
  BruteForceVa r;
  double best2 = 0.0;
  for (std::size_t i = 0; i < e.size(); ++i)
    for (std::size_t j = i + 1; j < e.size(); ++j) {
      const double dx = e[i].x() - e[j].x(), dy = e[i].y() - e[j].y(), dz = e[i].z() - e[j].z();
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 > best2) best2 = d2, r.i = i, r.j = j;
      r.component[0] = std::max(r.component[0], std::abs(dx));
      r.component[1] = std::max(r.component[1], std::abs(dy));
      r.component[2] = std::max(r.component[2], std::abs(dz));
    }
  r.va = std::sqrt(best2);
  return r;
}

std::vector<double> all_pair_distances(std::span<const Eigen::Vector3d> e) {
  std::vector<double> d;
  d.reserve(e.size() * (e.size() > 0 ? e.size() - 1 : 0) / 2);
  for (std::size_t i = 0; i < e.size(); ++i)
    for (std::size_t j = i + 1; j < e.size(); ++j) d.push_back((e[i] - e[j]).norm());
  return d;
}

}  // namespace mtcal::testing
