// Reference answers by exhaustive comparison of every pair, for tests and benchmark baselines.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace mtcal::testing {

struct BruteForceVa {
  double va = 0.0;                    // max |e_i - e_j|
  std::size_t i = 0, j = 0;           // a pair that gives it
  std::array<double, 3> component{};  // max |e_i,c - e_j,c|
};

// Compares all N (N - 1) / 2 pairs, O(N^2), no pruning.
BruteForceVa brute_force_va(std::span<const Eigen::Vector3d> e);

// Every pair distance, O(N^2) memory: only for small sets.
std::vector<double> all_pair_distances(std::span<const Eigen::Vector3d> e);

}  // namespace mtcal::testing
