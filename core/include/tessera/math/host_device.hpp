#pragma once
// One marker for code that runs on both CPU and GPU: shape, BSDF and traversal code is
// compiled by nvcc for the device from the same headers the CPU build uses.
#if defined(__CUDACC__)
#define TESSERA_HD __host__ __device__
#define TESSERA_INLINE __forceinline__
#define TESSERA_FORCE_INLINE __forceinline__
#else
#define TESSERA_HD
#define TESSERA_INLINE inline
// Where the host compiler's own choice was measured to be worse (see its uses).
#define TESSERA_FORCE_INLINE inline __attribute__((always_inline))
#endif
