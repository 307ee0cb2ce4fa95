#pragma once
// The compiled kernel sets of the SIMD triangle tracers, one namespace per instruction set.
#include "tessera/accel/triangle_accel.hpp"

namespace tessera::accel_detail {

#if defined(__x86_64__) || defined(_M_X64)
#define TESSERA_HAVE_SIMD_KERNELS 1
namespace sse2 {
const TriangleKernels& wide_kernels();
const TriangleKernels& brute_kernels();
}  // namespace sse2
namespace avx2 {
const TriangleKernels& wide_kernels();
const TriangleKernels& brute_kernels();
}  // namespace avx2
namespace avx512 {
const TriangleKernels& wide_kernels();
const TriangleKernels& brute_kernels();
}  // namespace avx512
#else
#define TESSERA_HAVE_SIMD_KERNELS 0
#endif

// True when the processor runs the AVX2 kernels (AVX2 plus the BMI1 bit scans they use).
bool cpu_has_avx2();
// True when it runs the AVX-512 kernels: the AVX2 set plus AVX-512 F, VL, BW and DQ, with
// the operating system saving their registers (which __builtin_cpu_supports checks).
bool cpu_has_avx512();

}  // namespace tessera::accel_detail
