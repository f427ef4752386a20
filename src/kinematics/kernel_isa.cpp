#include "mtcal/kinematics/kernel_isa.hpp"

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <string>

#include "../util/kernel.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// -1 until decided; otherwise the KernelIsa's value.
std::atomic<int> g_isa{-1};
std::mutex g_decide;

bool cpu_runs(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::Baseline:
      return true;
#if MTCAL_KERNEL_DISPATCH
    // __builtin_cpu_supports reports AVX features only where the operating system saves the
    // registers (XGETBV), so a level it reports can run.
    case KernelIsa::Avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
             __builtin_cpu_supports("bmi2");
    case KernelIsa::Avx512:
      return cpu_runs(KernelIsa::Avx2) && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512bw");
#else
    case KernelIsa::Avx2:
    case KernelIsa::Avx512:
      return false;
#endif
  }
  return false;
}

std::string accepted() { return "baseline, avx2 or avx512"; }

}  // namespace

std::string_view to_string(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::Baseline:
      return "baseline";
    case KernelIsa::Avx2:
      return "avx2";
    case KernelIsa::Avx512:
      return "avx512";
  }
  return "baseline";
}

std::optional<KernelIsa> parse_kernel_isa(std::string_view name) {
  for (KernelIsa isa : {KernelIsa::Baseline, KernelIsa::Avx2, KernelIsa::Avx512})
    if (name == to_string(isa)) return isa;
  return std::nullopt;
}

bool kernel_isa_supported(KernelIsa isa) { return cpu_runs(isa); }

std::vector<KernelIsa> supported_kernel_isas() {
  std::vector<KernelIsa> out;
  for (KernelIsa isa : {KernelIsa::Baseline, KernelIsa::Avx2, KernelIsa::Avx512})
    if (cpu_runs(isa)) out.push_back(isa);
  return out;
}

KernelIsa kernel_isa() {
  int v = g_isa.load(std::memory_order_acquire);
  if (v >= 0) return static_cast<KernelIsa>(v);
  const std::lock_guard lock(g_decide);
  v = g_isa.load(std::memory_order_relaxed);
  if (v >= 0) return static_cast<KernelIsa>(v);
  KernelIsa isa = supported_kernel_isas().back();
  if (const char* env = std::getenv("MTCAL_KERNEL_ISA"); env && *env) {
    const auto named = parse_kernel_isa(env);
    if (!named)
      throw ModelError("environment variable MTCAL_KERNEL_ISA: expected " + accepted() + ", found \"" +
                       printable(env) + "\"");
    if (!cpu_runs(*named))
      throw ModelError("environment variable MTCAL_KERNEL_ISA: " + std::string(to_string(*named)) +
                       " is not supported by this processor or build (supported: " +
                       std::string(to_string(supported_kernel_isas().back())) + " and below)");
    isa = *named;
  }
  g_isa.store(static_cast<int>(isa), std::memory_order_release);
  return isa;
}

void set_kernel_isa(KernelIsa isa) {
  if (!cpu_runs(isa))
    throw ModelError("kernel instruction set " + std::string(to_string(isa)) +
                     " is not supported by this processor or build");
  const std::lock_guard lock(g_decide);
  g_isa.store(static_cast<int>(isa), std::memory_order_release);
}

}  // namespace mtcal
