// Benchmarks of the rotary-axis estimators: 360 indexations (C(360,3) = 7.7 M triples) by the
// all-triples estimator (1 thread and all threads) against the global least-squares circle.
#include <vector>

#include <benchmark/benchmark.h>

#include "mtcal/probing/rotary_axis.hpp"
#include "synthetic.hpp"

namespace {

using namespace mtcal;

using mtcal::testing::circle_centres;

void BM_Triples_360(benchmark::State& state) {
  const auto c = circle_centres(360);
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (auto _ : state) {
    auto e = estimate_by_triples(axis, c, TriplesOptions{2.0, 40, static_cast<int>(state.range(0))});
    benchmark::DoNotOptimize(e.value.data());
  }
  state.counters["triples"] = static_cast<double>(360 * 359 * 358 / 6);
  state.SetItemsProcessed(state.iterations() * 360 * 359 * 358 / 6);
}

void BM_LeastSquares_360(benchmark::State& state) {
  const auto c = circle_centres(360);
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (auto _ : state) {
    auto e = estimate_by_least_squares(axis, c);
    benchmark::DoNotOptimize(e.value.data());
  }
}

void threads(benchmark::internal::Benchmark* b) {
  b->ArgName("threads");
  for (int t : mtcal::testing::thread_counts_to_compare()) b->Arg(t);
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Triples_360)->Apply(threads);

// 1,000 indexations: C(1000, 3) = 166 M triples, two passes (issue 18 target: <= 10 s on 2 cores).
void BM_Triples_1000(benchmark::State& state) {
  const auto c = circle_centres(1000);
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (auto _ : state) {
    auto e = estimate_by_triples(axis, c, TriplesOptions{2.0, 40, static_cast<int>(state.range(0))});
    benchmark::DoNotOptimize(e.value.data());
  }
  state.SetItemsProcessed(state.iterations() * 1000 * 999 * 998 / 6);
}
BENCHMARK(BM_Triples_1000)->ArgName("threads")->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LeastSquares_360)->Unit(benchmark::kMillisecond);

}  // namespace
