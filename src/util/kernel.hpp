// Internal: run-time CPU dispatch for hot loops (threads: mtcal/util/parallel.hpp).
#pragma once

// On x86-64 a hot loop is also compiled for AVX2 + FMA and picked at run time, so a portable
// build still uses the wider vectors where the processor has them.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MTCAL_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MTCAL_KERNEL_CLONES
#endif
