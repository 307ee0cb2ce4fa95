// SSE2 kernels: the x86-64 baseline, so they run on every 64-bit x86 processor.
#include "triangle_kernels.hpp"

#if TESSERA_HAVE_SIMD_KERNELS
#include <immintrin.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "tessera/accel/wide_node_sse.hpp"

#define TESSERA_KERNEL_NS sse2
#define TESSERA_KERNEL_ISA_NAME "sse2"
#define TESSERA_KERNEL_AVX2 0
#define TESSERA_KERNEL_AVX512 0
#include "triangle_kernels.inl"
#endif
