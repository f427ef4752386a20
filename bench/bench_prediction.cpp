// Benchmarks of `regress` (issue 18 target: 1,000 rows <= 1 s): every form fitted with its
// leave-one-out errors, by the hat-matrix formula (above FitOptions::loocv_refit_max) against
// the n refits it replaces (the baseline, on sizes where n refits still finish).
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "mtcal/prediction/regression.hpp"

namespace {

using namespace mtcal;

struct Data {
  std::vector<double> x, y;
};

// A thermal-growth curve of the size of Yaqoob 2017 Table 5.8 with 0.2 um noise.
Data growth(std::size_t n) {
  std::mt19937_64 gen(3);
  std::normal_distribution<double> noise(0.0, 2e-4);
  Data d;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 300.0 * static_cast<double>(i) / static_cast<double>(n - 1);
    d.x.push_back(t);
    d.y.push_back(0.01 - 0.0097 * std::exp(-0.045 * t) + noise(gen));
  }
  return d;
}

void fit_all(benchmark::State& state, std::size_t refit_max) {
  const Data d = growth(static_cast<std::size_t>(state.range(0)));
  FitOptions o;
  o.loocv_refit_max = refit_max;
  for (auto _ : state)
    for (const ModelSpec& s : all_model_specs()) benchmark::DoNotOptimize(fit_model(s, d.x, d.y, o).loocv_rmse);
  state.counters["rows"] = static_cast<double>(state.range(0));
}

// All 12 forms of `regress --models all`, leave-one-out by the hat matrix.
void BM_Regress_HatMatrix(benchmark::State& state) { fit_all(state, 0); }
BENCHMARK(BM_Regress_HatMatrix)->Arg(150)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);

// Baseline: the same with n refits (quadratic in n: 1,000 rows take about 50 s, so 150 here;
// the ratio at 150 rows is the speed-up there, and it grows linearly with n).
void BM_Regress_Refit_Baseline(benchmark::State& state) { fit_all(state, static_cast<std::size_t>(1) << 40); }
BENCHMARK(BM_Regress_Refit_Baseline)->Arg(150)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
