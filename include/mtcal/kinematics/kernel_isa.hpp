// The instruction set the batched error kernels run on, chosen at run time from the processor.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace mtcal {

// One binary carries each kernel for every level below and uses the widest the processor has
// (docs/performance.md, "Run-time dispatch"). Every level gives the same bits: the kernels are
// compiled without floating-point contraction, so the levels differ only in vector width.
enum class KernelIsa { Baseline, Avx2, Avx512 };

// "baseline", "avx2", "avx512".
std::string_view to_string(KernelIsa isa);
std::optional<KernelIsa> parse_kernel_isa(std::string_view name);

// Whether this build carries the level and this processor (and its operating system) runs it.
bool kernel_isa_supported(KernelIsa isa);
std::vector<KernelIsa> supported_kernel_isas();

// The level in use. Decided at the first call: the environment variable MTCAL_KERNEL_ISA when set
// (a ModelError if it names no level or one the processor lacks), else the widest supported.
KernelIsa kernel_isa();
// For the whole process (tests, benchmarks); a ModelError if the level is not supported.
void set_kernel_isa(KernelIsa isa);

}  // namespace mtcal
