// AVX-512 kernels: the kernels' source compiled with AVX-512 F, VL, BW and DQ allowed, by a
// target pragma as the AVX2 file does. Node tests stay eight lanes wide; what AVX-512 adds
// is 32 vector registers instead of 16 (the ray's constants are not reloaded from the stack
// at every node), compares that write mask registers, and leaves of three or four triangle
// blocks tested in one sixteen-lane pass (TESSERA_KERNEL_AVX512 in the .inl). Measured
// against the AVX2 build (alternating runs, bench/accel/README.md): the recompilation alone
// gave diffuse rays +0 to +1.7% and primary rays +0.4%, the sixteen-lane leaves another
// +2 to +6% on diffuse rays. Allowing the compiler to fuse multiplies and adds would have
// given +1 to +3% more, but broke bit-equality with the scalar triangle test
// (core/CMakeLists.txt turns contraction off for these files).
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
bool cpu_has_avx512() {
  __builtin_cpu_init();
  return cpu_has_avx2() && __builtin_cpu_supports("avx512f") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512dq");
}
}  // namespace tessera::accel_detail

#if defined(__clang__)
#pragma clang attribute push(                                                      \
    __attribute__((target("avx2,bmi,popcnt,avx512f,avx512vl,avx512bw,avx512dq"))), \
    apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,bmi,popcnt,avx512f,avx512vl,avx512bw,avx512dq")
// GCC 12's AVX-512 intrinsics (_mm512_broadcastss_ps, _mm512_reduce_min_ps) pass
// _mm512_undefined_ps() as the unused merge source, which -Wmaybe-uninitialized reports
// (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#define TESSERA_KERNEL_NS avx512
#define TESSERA_KERNEL_ISA_NAME "avx512"
#define TESSERA_KERNEL_AVX2 1
#define TESSERA_KERNEL_AVX512 1
#include "triangle_kernels.inl"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif
#else
namespace tessera::accel_detail {
bool cpu_has_avx512() {
  return false;
}
}  // namespace tessera::accel_detail
#endif
