// The yardstick of the compile-time check (scripts/build-times, docs/building.md): a unit like the
// project's own (Eigen, the standard containers, some code to optimise) compiled three times in every
// build, at fixed flags, without ccache or a precompiled header. Every unit's compile time is divided
// by this one's from the same run. Changing this file changes the yardstick: re-record
// tests/buildtime/record.json (docs/building.md).
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mtcal_build_baseline {

double solve(const std::vector<double>& values) {
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t i = 0; i < values.size(); ++i) {
    a(static_cast<Eigen::Index>(i % 6), static_cast<Eigen::Index>((i * 5) % 6)) += values[i];
    b(static_cast<Eigen::Index>(i % 6)) += values[i] * 0.5;
  }
  return a.partialPivLu().solve(b).norm();
}

std::map<std::string, double> tally(const std::vector<std::string>& names, const std::vector<double>& values) {
  std::map<std::string, double> out;
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) out[names[i]] += values[i];
  std::vector<std::string> sorted = names;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  out["#distinct"] = static_cast<double>(sorted.size());
  return out;
}

}  // namespace mtcal_build_baseline
