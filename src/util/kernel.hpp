// Internal: run-time CPU dispatch for hot loops (threads: mtcal/util/parallel.hpp).
#pragma once

// The error kernels (kinematics/batch.cpp) are compiled once per instruction-set level with these
// function attributes and picked at run time (mtcal/kinematics/kernel_isa.hpp). Function
// attributes rather than separately compiled files: only the kernel bodies and what is inlined
// into them use the wider instructions, never an inline library function the linker could pick
// for the rest of the program. Both GCC and clang accept these feature lists.
#if defined(__x86_64__) && defined(__GNUC__)
#define MTCAL_KERNEL_DISPATCH 1
#define MTCAL_TARGET_AVX2 __attribute__((target("avx2,fma,bmi,bmi2")))
#define MTCAL_TARGET_AVX512 __attribute__((target("avx512f,avx512cd,avx512vl,avx512dq,avx512bw,avx2,fma,bmi,bmi2")))
#else
#define MTCAL_KERNEL_DISPATCH 0
#endif

// A lesser hot loop (volumetric.cpp) is also compiled for AVX2 + FMA and picked by the compiler's
// own target_clones dispatch.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MTCAL_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MTCAL_KERNEL_CLONES
#endif
