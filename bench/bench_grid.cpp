// Benchmarks of grid evaluation (issue 18): `eval --grid` on the HU40T example, single thread,
// by the grid kernel (each axis' transforms once per grid value, ErrorModel::evaluate_grid inside
// evaluate_stream) against the point-by-point kernel on the same configurations (baseline, same
// run), and the stream with its CSV written (target: within 1.5x of the kernel alone).
// Items are configurations: items_per_second is configurations/s on one core.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "kernel_level.hpp"

namespace {

using namespace mtcal;

struct Setup {
  Machine m;
  GridValues grid;
};

// 16^5 = 1,048,576 or 19 x 20^4 = 3,040,000 configurations (the sizes of bench/grid_peer.py).
Setup hu40t(std::int64_t size) {
  Setup s{load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml"), {}};
  const std::string spec = size <= 1048576 ? "C=-180:180:16,B=-90:90:16,X=-300:300:16,Y=-250:250:16,Z=-300:300:16"
                                           : "C=-180:180:19,B=-90:90:20,X=-300:300:20,Y=-250:250:20,Z=-300:300:20";
  s.grid = parse_grid(s.m, spec, "bench");
  return s;
}

// evaluate_stream over the grid: what `eval --grid --threads 1` does without --out.
void BM_EvalGrid_Hu40t(benchmark::State& state) {
  const Setup s = hu40t(state.range(0));
  const ErrorModel model(s.m);
  const auto source = ConfigurationSource::grid(s.grid);
  StreamOptions o;
  o.threads = 1;
  for (auto _ : state) benchmark::DoNotOptimize(evaluate_stream(model, source, {}, o).max_translation.value);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(source.size()));
}
BENCHMARK(BM_EvalGrid_Hu40t)->Arg(1048576)->Arg(3040000)->Unit(benchmark::kMillisecond);

// The grid kernel alone on `points` configurations, chunk by chunk into one reused buffer.
void grid_kernel(benchmark::State& state, std::int64_t points) {
  const Setup s = hu40t(points);
  const ErrorModel model(s.m);
  const std::size_t total = grid_count(s.grid), chunk = std::size_t{1} << 20;
  std::vector<double> out(std::min(total, chunk) * 6);
  for (auto _ : state)
    for (std::size_t first = 0; first < total; first += chunk) {
      const std::size_t len = std::min(chunk, total - first);
      model.evaluate_grid(s.grid, first, std::span(out).first(len * 6), {1});
      benchmark::DoNotOptimize(out.data());
    }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(total));
#ifdef MTCAL_BENCH_ISA
  state.counters["flops_per_config"] = model.grid_flops_per_configuration();
#endif
}
void BM_GridKernel_Hu40t(benchmark::State& state) { grid_kernel(state, state.range(0)); }
BENCHMARK(BM_GridKernel_Hu40t)->Arg(1048576)->Arg(3040000)->Unit(benchmark::kMillisecond);

#ifdef MTCAL_BENCH_ISA
// The grid kernel at 1e6 on each instruction-set level (0 baseline, 1 AVX2, 2 AVX-512).
void BM_GridKernelIsa_Hu40t(benchmark::State& state) {
  const mtcal::bench::KernelLevel level(state);
  if (level.ok()) grid_kernel(state, 1048576);
}
BENCHMARK(BM_GridKernelIsa_Hu40t)->ArgName("isa")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
#endif

// Baseline: the point-by-point kernel (evaluate_batch) on the same configurations, chunk by chunk.
void BM_GridPointByPoint_Hu40t_Baseline(benchmark::State& state) {
  const Setup s = hu40t(state.range(0));
  const ErrorModel model(s.m);
  const auto source = ConfigurationSource::grid(s.grid);
  const std::size_t total = source.size(), chunk = std::size_t{1} << 20, n = s.m.axes.size();
  std::vector<double> q(std::min(total, chunk) * n), out(std::min(total, chunk) * 6);
  for (auto _ : state)
    for (std::size_t first = 0; first < total; first += chunk) {
      const std::size_t len = std::min(chunk, total - first);
      source.fill_range(first, len, q.data(), nullptr);
      model.evaluate_batch(std::span(q).first(len * n), {}, std::span(out).first(len * 6), {1});
      benchmark::DoNotOptimize(out.data());
    }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(total));
}
BENCHMARK(BM_GridPointByPoint_Hu40t_Baseline)->Arg(1048576)->Unit(benchmark::kMillisecond)->Iterations(1);

// The stream with its CSV (`eval --grid --out`), threads as given (the formatting is parallel).
void BM_EvalGridCsv_Hu40t(benchmark::State& state) {
  const Setup s = hu40t(1048576);
  const ErrorModel model(s.m);
  const auto source = ConfigurationSource::grid(s.grid);
  const std::string path = (std::filesystem::temp_directory_path() / "mtcal_bench_grid.csv").string();
  const int threads = static_cast<int>(state.range(0));
  StreamOptions o;
  o.threads = threads;
  for (auto _ : state) {
    ErrorStreamCsv csv(path, s.m, false, threads);
    evaluate_stream(
        model, source, [&](const ErrorChunk& c) { csv.write(c); }, o);
    csv.commit();
  }
  std::remove(path.c_str());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(source.size()));
}
BENCHMARK(BM_EvalGridCsv_Hu40t)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The stream with a NumPy array file (`eval --grid --out FILE.npy`): the doubles as they are.
void BM_EvalGridNpy_Hu40t(benchmark::State& state) {
  const Setup s = hu40t(state.range(0));
  const ErrorModel model(s.m);
  const auto source = ConfigurationSource::grid(s.grid);
  const std::string path = (std::filesystem::temp_directory_path() / "mtcal_bench_grid.npy").string();
  StreamOptions o;
  o.threads = 1;
  for (auto _ : state) {
    ErrorStreamNpy npy(path, s.m, false);
    evaluate_stream(
        model, source, [&](const ErrorChunk& c) { npy.write(c); }, o);
    npy.commit();
  }
  std::remove(path.c_str());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(source.size()));
}
BENCHMARK(BM_EvalGridNpy_Hu40t)->Arg(1048576)->Arg(3040000)->Unit(benchmark::kMillisecond);

}  // namespace
