// Benchmarks of the exact error model: batched kernel (1 thread and all threads) on the shipped
// 3-axis example and a full synthetic 5-axis machine, a naive 4x4-matrix baseline of the same
// maths, and the scalar evaluate / Jacobian. Every benchmark reports items_per_second in
// configurations per second.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Core>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "kernel_level.hpp"
#include "../src/util/kernel.hpp"
#include "mtcal/model/machine.hpp"
#include "naive_chain.hpp"
#include "synthetic.hpp"

namespace {

using mtcal::ErrorModel;
using mtcal::Machine;

constexpr std::size_t kBatch = 65536;
constexpr std::size_t kChecked = 100;  // configurations checked against ErrorModel::evaluate
constexpr double kTolerance = 1e-12;   // mm / rad
constexpr std::uint64_t kConfigSeed = 20240601;
constexpr std::uint64_t kErrorSeed = 7;

// A machine compiled for evaluation and a batch of random configurations with directions.
struct Case {
  explicit Case(Machine m) : model(m), machine(std::move(m)) {
    q = mtcal::testing::random_configurations(machine, kBatch, kConfigSeed, &dir);
  }
  ErrorModel model;
  Machine machine;
  std::vector<double> q;
  std::vector<std::int8_t> dir;
  std::size_t axes() const { return machine.axes.size(); }
};

Machine three_axis_machine() { return mtcal::load_machine(MTCAL_EXAMPLES_DIR "/vmc-3axis.yaml"); }

Machine five_axis_machine() {
  // Every parameter non-zero: 30 motion errors as cubics with reversal, all location errors,
  // tool and workpiece mounting.
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, kErrorSeed);
  return m;
}

Machine hu40t_machine() { return mtcal::load_machine(MTCAL_EXAMPLES_DIR "/hu40t-wCBXfYZt.yaml"); }

// The same machine with every Fourier series and table replaced by a cubic with reversal of the
// same size: the baseline of what those forms cost over polynomials.
Machine as_polynomials(Machine m) {
  for (auto& ax : m.axes)
    for (auto& f : ax.motion)
      if (!std::holds_alternative<mtcal::Polynomial>(f.form()) && !f.is_zero()) {
        const double size = std::abs(f.value(0.3, 1)) + 1e-9;
        f = mtcal::MotionFunction(mtcal::Polynomial{{size, size * 1e-3, -size * 1e-6, size * 1e-9}, size * 0.1});
      }
  return m;
}

enum class Which { ThreeAxis, FiveAxis, Hu40t, Hu40tPolynomial, ThreeAxisPolynomial, kCount };

// Built once per process; on failure returns null and sets error.
const Case* get_case(Which which, std::string& error) {
  constexpr auto kCases = static_cast<std::size_t>(Which::kCount);
  static std::unique_ptr<Case> cases[kCases];
  static std::string errors[kCases];
  static bool built[kCases] = {};
  const auto i = static_cast<std::size_t>(which);
  if (!built[i]) {
    built[i] = true;
    try {
      switch (which) {
        case Which::ThreeAxis:
          cases[i] = std::make_unique<Case>(three_axis_machine());
          break;
        case Which::FiveAxis:
          cases[i] = std::make_unique<Case>(five_axis_machine());
          break;
        case Which::Hu40t:
          cases[i] = std::make_unique<Case>(hu40t_machine());
          break;
        case Which::Hu40tPolynomial:
          cases[i] = std::make_unique<Case>(as_polynomials(hu40t_machine()));
          break;
        default:
          cases[i] = std::make_unique<Case>(as_polynomials(three_axis_machine()));
          break;
      }
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  }
  error = errors[i];
  return cases[i].get();
}

std::span<const double> config(const Case& c, std::size_t i) {
  return std::span<const double>(c.q).subspan(i * c.axes(), c.axes());
}
std::span<const std::int8_t> direction(const Case& c, std::size_t i) {
  return std::span<const std::int8_t>(c.dir).subspan(i * c.axes(), c.axes());
}

// ---------------------------------------------------------------- batched kernel

void batch(benchmark::State& state, Which which, int threads) {
  std::string error;
  const Case* c = get_case(which, error);
  if (!c) {
    state.SkipWithError(error.c_str());
    return;
  }
  const mtcal::BatchOptions options{threads};
  std::vector<double> out(kBatch * 6);
  for (auto _ : state) {
    c->model.evaluate_batch(c->q, c->dir, out, options);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBatch));
#ifdef MTCAL_BENCH_ISA
  state.counters["flops_per_config"] = c->model.batch_flops_per_configuration();
#endif
}

void BM_Batch_3axis(benchmark::State& state) { batch(state, Which::ThreeAxis, static_cast<int>(state.range(0))); }
void BM_Batch_5axis(benchmark::State& state) { batch(state, Which::FiveAxis, static_cast<int>(state.range(0))); }

void thread_args(benchmark::internal::Benchmark* b) {
  b->ArgName("threads");
  for (int t : mtcal::testing::thread_counts_to_compare()) b->Arg(t);
  // Worker threads do the work: wall-clock time is the meaningful rate.
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Batch_3axis)->Apply(thread_args);
BENCHMARK(BM_Batch_5axis)->Apply(thread_args);

// ---------------------------------------------------------------- motion-error forms, kernel levels

// One thread, the kernel level in use: the shipped HU40T (Fourier series on B and C) and the
// 3-axis VMC (a table) against the same machines with polynomials in their place.
void BM_Forms_Hu40t(benchmark::State& state) { batch(state, Which::Hu40t, 1); }
void BM_Forms_Hu40tPolynomial_Baseline(benchmark::State& state) { batch(state, Which::Hu40tPolynomial, 1); }
void BM_Forms_3axisTable(benchmark::State& state) { batch(state, Which::ThreeAxis, 1); }
void BM_Forms_3axisPolynomial_Baseline(benchmark::State& state) { batch(state, Which::ThreeAxisPolynomial, 1); }
BENCHMARK(BM_Forms_Hu40t)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Forms_Hu40tPolynomial_Baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Forms_3axisTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Forms_3axisPolynomial_Baseline)->Unit(benchmark::kMillisecond);

#ifdef MTCAL_BENCH_ISA
// Each instruction-set level (0 baseline, 1 AVX2, 2 AVX-512; kernel_isa.hpp), one thread: the
// synthetic 5-axis machine (polynomials), the HU40T (Fourier) and the 3-axis VMC (table).
void isa_batch(benchmark::State& state, Which which) {
  const mtcal::bench::KernelLevel level(state);
  if (level.ok()) batch(state, which, 1);
}
void BM_Isa_5axis(benchmark::State& state) { isa_batch(state, Which::FiveAxis); }
void BM_Isa_Hu40t(benchmark::State& state) { isa_batch(state, Which::Hu40t); }
void BM_Isa_3axis(benchmark::State& state) { isa_batch(state, Which::ThreeAxis); }
BENCHMARK(BM_Isa_5axis)->ArgName("isa")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Isa_Hu40t)->ArgName("isa")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Isa_3axis)->ArgName("isa")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// The machine's limit for these kernels: independent multiply-then-add chains (the kernels are
// built without fused multiply-add, src/CMakeLists.txt; so is this file), 12 vectors of the level's
// width in registers (24 doubles in SSE2, 48 in AVX2, 96 in AVX-512: the first two have 16 vector
// registers, so more chains would spill). Items are floating-point operations: flop/s.
template <int Lanes>
[[gnu::always_inline]] inline void peak_chains(double* acc, std::int64_t rounds) {
  double x[Lanes];
  for (int i = 0; i < Lanes; ++i) x[i] = acc[i];
  for (std::int64_t r = 0; r < rounds; ++r) {
#pragma GCC unroll 96
    for (int i = 0; i < Lanes; ++i) x[i] = x[i] * 0.9999999 + 1e-7;
  }
  for (int i = 0; i < Lanes; ++i) acc[i] = x[i];
}
#define MTCAL_BENCH_PEAK(ATTR, SUFFIX, LANES) \
  ATTR void peak_##SUFFIX(double* acc, std::int64_t rounds) { peak_chains<LANES>(acc, rounds); }
// The kernels' own level attributes (src/util/kernel.hpp), so that the limit is measured on the
// instruction sets the kernels are built for.
MTCAL_BENCH_PEAK(, baseline, 24)
#if MTCAL_KERNEL_DISPATCH
MTCAL_BENCH_PEAK(MTCAL_TARGET_AVX2, avx2, 48)
MTCAL_BENCH_PEAK(MTCAL_TARGET_AVX512, avx512, 96)
#endif

void BM_PeakMulAdd(benchmark::State& state) {
  const mtcal::bench::KernelLevel level(state);
  if (!level.ok()) return;
  const auto isa = mtcal::kernel_isa();
  auto* run = &peak_baseline;
  std::int64_t lanes = 24;
#if MTCAL_KERNEL_DISPATCH
  if (isa == mtcal::KernelIsa::Avx2) run = &peak_avx2, lanes = 48;
  if (isa == mtcal::KernelIsa::Avx512) run = &peak_avx512, lanes = 96;
#endif
  std::vector<double> acc(96, 1.0);
  constexpr std::int64_t kRounds = 1 << 16;
  for (auto _ : state) {
    run(acc.data(), kRounds);
    benchmark::DoNotOptimize(acc.data());
  }
  state.SetItemsProcessed(state.iterations() * kRounds * lanes * 2);
}
BENCHMARK(BM_PeakMulAdd)->ArgName("isa")->DenseRange(0, 2);
#endif

// ---------------------------------------------------------------- naive baseline

void naive(benchmark::State& state, Which which) {
  std::string error;
  const Case* c = get_case(which, error);
  if (!c) {
    state.SkipWithError(error.c_str());
    return;
  }
  // The baseline must compute the same thing as the model.
  double max_diff = 0.0;
  for (std::size_t i = 0; i < std::min(kChecked, kBatch); ++i) {
    const auto ref = c->model.evaluate(config(*c, i), direction(*c, i));
    const auto nv = mtcal::bench::naive_evaluate(c->machine, config(*c, i), direction(*c, i));
    const double d = std::max((ref.translation - nv.translation).cwiseAbs().maxCoeff(),
                              (ref.rotation - nv.rotation).cwiseAbs().maxCoeff());
    if (!(d <= kTolerance)) {  // also catches NaN
      const std::string msg = "naive baseline differs from ErrorModel::evaluate at configuration " + std::to_string(i) +
                              " by " + std::to_string(d);
      state.SkipWithError(msg.c_str());
      return;
    }
    max_diff = std::max(max_diff, d);
  }
  std::vector<double> out(kBatch * 6);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const auto v = mtcal::bench::naive_evaluate(c->machine, config(*c, i), direction(*c, i));
      for (int j = 0; j < 3; ++j) {
        out[6 * i + static_cast<std::size_t>(j)] = v.translation[j];
        out[6 * i + 3 + static_cast<std::size_t>(j)] = v.rotation[j];
      }
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBatch));
  state.counters["check_max_diff"] = max_diff;
}

void BM_Naive_3axis(benchmark::State& state) { naive(state, Which::ThreeAxis); }
void BM_Naive_5axis(benchmark::State& state) { naive(state, Which::FiveAxis); }

BENCHMARK(BM_Naive_3axis)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Naive_5axis)->Unit(benchmark::kMillisecond);

// ---------------------------------------------------------------- scalar paths (5-axis)

void BM_Evaluate_5axis(benchmark::State& state) {
  std::string error;
  const Case* c = get_case(Which::FiveAxis, error);
  if (!c) {
    state.SkipWithError(error.c_str());
    return;
  }
  std::size_t i = 0;
  for (auto _ : state) {
    auto v = c->model.evaluate(config(*c, i), direction(*c, i));
    benchmark::DoNotOptimize(v);
    i = (i + 1) % kBatch;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Evaluate_5axis);

void BM_Jacobian_5axis(benchmark::State& state) {
  std::string error;
  const Case* c = get_case(Which::FiveAxis, error);
  if (!c) {
    state.SkipWithError(error.c_str());
    return;
  }
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, static_cast<Eigen::Index>(c->machine.parameter_count()));
  mtcal::JacobianWorkspace ws;
  std::size_t i = 0;
  for (auto _ : state) {
    c->model.jacobian(config(*c, i), direction(*c, i), J, ws);
    benchmark::DoNotOptimize(J.data());
    benchmark::ClobberMemory();
    i = (i + 1) % kBatch;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["parameters"] = static_cast<double>(c->machine.parameter_count());
}
BENCHMARK(BM_Jacobian_5axis);

}  // namespace

BENCHMARK_MAIN();
