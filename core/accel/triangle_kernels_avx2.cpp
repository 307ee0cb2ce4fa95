// AVX2 kernels, compiled for AVX2 by a target pragma rather than a global -mavx2, so the
// rest of the library keeps the baseline instruction set and the dispatcher can choose
// these only on processors that have it. FMA is deliberately not enabled (see the .inl).
#include "triangle_kernels.hpp"

#if TESSERA_HAVE_SIMD_KERNELS
#include <immintrin.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "tessera/accel/wide_node_sse.hpp"

namespace tessera::accel_detail {
bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") &&
         __builtin_cpu_supports("popcnt");
}
}  // namespace tessera::accel_detail

// Clang ignores GCC's target pragma; its attribute pragma does the same (the fuzz build,
// `make fuzz`, compiles the library with clang).
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,bmi,popcnt"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,bmi,popcnt")
#endif
#define TESSERA_KERNEL_NS avx2
#define TESSERA_KERNEL_ISA_NAME "avx2"
#define TESSERA_KERNEL_AVX2 1
#define TESSERA_KERNEL_AVX512 0
#include "triangle_kernels.inl"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#else
namespace tessera::accel_detail {
bool cpu_has_avx2() {
  return false;
}
}  // namespace tessera::accel_detail
#endif
