// Benchmarks on one instruction-set level of the error kernels (mtcal/kinematics/kernel_isa.hpp).
#pragma once

#if __has_include("mtcal/kinematics/kernel_isa.hpp")  // absent before run-time dispatch (old-build baselines)
#define MTCAL_BENCH_ISA 1
#include <string>

#include <benchmark/benchmark.h>

#include "mtcal/kinematics/kernel_isa.hpp"

namespace mtcal::bench {

// Switches the process to the level state.range(0) names (0 baseline, 1 AVX2, 2 AVX-512) for the
// benchmark's life and labels it; ok() is false (and the benchmark skipped) where the processor
// lacks the level.
class KernelLevel {
 public:
  explicit KernelLevel(benchmark::State& state)
      : saved_(kernel_isa()), ok_(kernel_isa_supported(static_cast<KernelIsa>(state.range(0)))) {
    const auto isa = static_cast<KernelIsa>(state.range(0));
    if (!ok_) {
      state.SkipWithError("this processor lacks the level");
      return;
    }
    set_kernel_isa(isa);
    state.SetLabel(std::string(to_string(isa)));
  }
  ~KernelLevel() { set_kernel_isa(saved_); }
  KernelLevel(const KernelLevel&) = delete;
  KernelLevel& operator=(const KernelLevel&) = delete;
  bool ok() const { return ok_; }

 private:
  KernelIsa saved_;
  bool ok_;
};

}  // namespace mtcal::bench
#endif
