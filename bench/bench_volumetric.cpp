// Benchmarks of volumetric accuracy (issue targets): exact VA of the 21^3 map of the 3-axis
// example against the O(N^2) comparison of every pair; the exact pair histogram over its
// 42.9 M pairs; synthesis plus exact VA of a 101^3 grid (1.03 M points).
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "brute_force.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"

namespace {

using namespace mtcal;

const Machine& vmc() {
  static const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  return m;
}

std::string grid(int n) {
  return "X=-400:400:" + std::to_string(n) + ",Y=-250:250:" + std::to_string(n) + ",Z=-500:0:" + std::to_string(n);
}

const ErrorMap& map21() {
  static const ErrorMap map = grid_error_map(ErrorModel(vmc()), parse_grid(vmc(), grid(21), "bench grid"));
  return map;
}

// Exact VA after synthesis (the target: <= 10 ms).
void BM_VA_Exact_21cubed(benchmark::State& state) {
  const auto& e = map21().error;
  for (auto _ : state) benchmark::DoNotOptimize(volumetric_accuracy(e).va.value);
  state.counters["points"] = static_cast<double>(e.size());
}
BENCHMARK(BM_VA_Exact_21cubed)->Unit(benchmark::kMillisecond);

// The same search without its starting pair: what the tree alone costs.
void BM_VA_TreeOnly_21cubed(benchmark::State& state) {
  const auto& e = map21().error;
  for (auto _ : state) benchmark::DoNotOptimize(volumetric_accuracy(e, {.initial_bound = false}).va.value);
}
BENCHMARK(BM_VA_TreeOnly_21cubed)->Unit(benchmark::kMillisecond);

// Baseline: compare every pair (Fletcher's own method, 42.9 M comparisons).
void BM_VA_BruteForce_21cubed(benchmark::State& state) {
  const auto& e = map21().error;
  for (auto _ : state) benchmark::DoNotOptimize(::mtcal::testing::brute_force_va(e).va);
}
BENCHMARK(BM_VA_BruteForce_21cubed)->Unit(benchmark::kMillisecond);

// Fletcher's grouping at his tolerances (Table 1) with the default magnitude 0.9.
void BM_VA_FletcherGrouping_21cubed(benchmark::State& state) {
  const auto& e = map21().error;
  const double tol = static_cast<double>(state.range(0)) / 100.0;
  GroupingResult r;
  for (auto _ : state) benchmark::DoNotOptimize((r = fletcher_grouping(e, {tol, 0.9})).va.value);
  state.counters["kept"] = static_cast<double>(r.kept.size());
}
BENCHMARK(BM_VA_FletcherGrouping_21cubed)->Arg(5)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);

// Every one of the 42.9 M pair distances binned (target <= 200 ms on 2 cores); argument: threads.
void BM_PairHistogram_21cubed(benchmark::State& state) {
  const auto& e = map21().error;
  for (auto _ : state) benchmark::DoNotOptimize(pair_distribution(e, 100, 0.0, static_cast<int>(state.range(0))).mean);
  state.counters["pairs/s"] = benchmark::Counter(static_cast<double>(e.size()) * static_cast<double>(e.size() - 1) / 2,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_PairHistogram_21cubed)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Synthesis of the 101^3 grid and its exact VA (target <= 1 s); argument: threads.
void BM_MapAndVA_101cubed(benchmark::State& state) {
  const ErrorModel model(vmc());
  const auto values = parse_grid(vmc(), grid(101), "bench grid");
  for (auto _ : state) {
    const ErrorMap map = grid_error_map(model, values, {static_cast<int>(state.range(0))});
    benchmark::DoNotOptimize(volumetric_accuracy(map.error).va.value);
  }
}
BENCHMARK(BM_MapAndVA_101cubed)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Its parts: synthesis alone and the exact VA alone.
void BM_Map_101cubed(benchmark::State& state) {
  const ErrorModel model(vmc());
  const auto values = parse_grid(vmc(), grid(101), "bench grid");
  for (auto _ : state) benchmark::DoNotOptimize(grid_error_map(model, values, {2}).error.data());
}
BENCHMARK(BM_Map_101cubed)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_VA_Exact_101cubed(benchmark::State& state) {
  static const ErrorMap map = grid_error_map(ErrorModel(vmc()), parse_grid(vmc(), grid(101), "bench grid"));
  VolumetricAccuracy r;
  for (auto _ : state) benchmark::DoNotOptimize((r = volumetric_accuracy(map.error)).va.value);
  state.counters["distances"] = static_cast<double>(r.distance_evaluations);
}
BENCHMARK(BM_VA_Exact_101cubed)->Unit(benchmark::kMillisecond);

}  // namespace

// ---------------------------------------------------------------------------------------------
// Bounded memory (issue 18, item 4): the exact VA of the HU40T example over a 4^5 x ... grid of
// 1,048,576 configurations on one thread. Baseline: the map held (64 MB of configurations and
// errors for this grid) and searched; against it the streamed passes (memory independent of the
// grid size: bench/README, docs/performance.md), configuration by configuration (/0: the same
// bits) and with the grid kernel (/1).
namespace {

const Machine& hu40t() {
  static const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  return m;
}
const GridValues& hu40t_grid() {
  static const GridValues g =
      parse_grid(hu40t(), "X=-300:300:16,Y=-250:250:16,Z=-300:0:16,B=-90:90:16,C=0:360:16", "bench grid");
  return g;
}

}  // namespace

void BM_VolumetricInMemory_Hu40t_Baseline(benchmark::State& state) {
  const ErrorModel model(hu40t());
  for (auto _ : state) {
    const ErrorMap map = grid_error_map(model, hu40t_grid(), {1});
    benchmark::DoNotOptimize(volumetric_accuracy(map.error).va.value);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(grid_count(hu40t_grid())));
}
BENCHMARK(BM_VolumetricInMemory_Hu40t_Baseline)->Unit(benchmark::kMillisecond);

void BM_VolumetricStream_Hu40t(benchmark::State& state) {
  const ErrorModel model(hu40t());
  StreamOptions so;
  so.threads = 1;
  so.grid_kernel = state.range(0) != 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(streamed_volumetric_accuracy(model, ConfigurationSource::grid(hu40t_grid()), so).va.value);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(grid_count(hu40t_grid())));
}
BENCHMARK(BM_VolumetricStream_Hu40t)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
