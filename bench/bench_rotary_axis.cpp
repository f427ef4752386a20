// Benchmarks of the rotary-axis estimators: 360 indexations (C(360,3) = 7.7 M triples) by the
// all-triples estimator (1 thread and all threads) against the global least-squares circle.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "mtcal/probing/rotary_axis.hpp"

namespace {

using namespace mtcal;

// Sphere centres on a slightly tilted, offset circle with 1 um noise, one per degree.
std::vector<MeasuredCentre> centres(std::size_t n) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 1e-3);
  const Point3 axis_point(0.01, -0.02, 0.0), normal = Point3(3e-5, -2e-5, 1.0).normalized();
  const Point3 u = normal.cross(Point3::UnitX()).normalized(), v = normal.cross(u);
  std::vector<MeasuredCentre> out;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const Point3 p = axis_point + 120.0 * (std::cos(a) * u + std::sin(a) * v) + 80.0 * normal;
    out.push_back({a, p + Point3(noise(rng), noise(rng), noise(rng))});
  }
  return out;
}

void BM_Triples_360(benchmark::State& state) {
  const auto c = centres(360);
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (auto _ : state) {
    auto e = estimate_by_triples(axis, c, TriplesOptions{2.0, 40, static_cast<int>(state.range(0))});
    benchmark::DoNotOptimize(e.value.data());
  }
  state.counters["triples"] = static_cast<double>(360 * 359 * 358 / 6);
  state.SetItemsProcessed(state.iterations() * 360 * 359 * 358 / 6);
}

void BM_LeastSquares_360(benchmark::State& state) {
  const auto c = centres(360);
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (auto _ : state) {
    auto e = estimate_by_least_squares(axis, c);
    benchmark::DoNotOptimize(e.value.data());
  }
}

void threads(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Arg(1);
  const int all = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (all > 1) b->Arg(all);
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Triples_360)->Apply(threads);
BENCHMARK(BM_LeastSquares_360)->Unit(benchmark::kMillisecond);

}  // namespace
