#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "tessera/math/vec.hpp"

#if !defined(__CUDACC__) && (defined(__SSE2__) || defined(_M_X64))
#define TESSERA_OFFSET_RAY_SSE2 1
#include <emmintrin.h>
#else
#define TESSERA_OFFSET_RAY_SSE2 0
#endif

namespace tessera {

// Spawn-point offset by Wächter and Binder ("A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6): move the hit point off the surface by a
// fixed number of ulps along the geometric normal, which scales with the magnitude of the
// coordinates instead of using an epsilon that fails far from the origin.
namespace detail {
TESSERA_HD TESSERA_INLINE float int_as_float(std::int32_t i) {
  float f;
  std::memcpy(&f, &i, sizeof f);
  return f;
}
TESSERA_HD TESSERA_INLINE std::int32_t float_as_int(float f) {
  std::int32_t i;
  std::memcpy(&i, &f, sizeof i);
  return i;
}
}  // namespace detail

// How far offset_ray_origin moves a coordinate: kSpawnUlps units in the last place along the
// normal (times its component), or, within kSpawnBand of zero, where ulps vanish, a fixed
// kSpawnStep: Wächter and Binder's constants, the band and step times `spawn_scale` (below).
// Fewer ulps would help scenes far from the origin: at 1,000 units 256 ulps are 1.5 cm, and
// RayON's colour-bleed box moved there loses the ceiling's light through its 1 cm slit
// (1.06% dark). But a hit point's error is a few ulps of the coordinates it was computed
// from, not of its own: 16 ulps with a band of 8 fixed that box and turned a scene with a
// tilted ground triangle 18 km across 0.7% dark, by self-intersection near the origin, where
// 256 ulps of 1/32 and more cover it. Offsets from each primitive's own coordinates would
// serve both; until then the constants stay.
inline constexpr float kSpawnUlps = 256.0f;
inline constexpr float kSpawnStep = 1.0f / 65536.0f;
inline constexpr float kSpawnBand = 1.0f / 32.0f;

// `spawn_scale` is 1 for scenes of a few units and more, and a power of two proportional to
// the scene's extent below that (spawn_scale_for_extent), so a scene built in millimetres as
// metres spawns its rays at the same relative distance, instead of 1.5e-5 units off every
// surface near the origin, which stepped over a 10-micrometre gap. Every coordinate of such a
// scene, and so every hit point's error, shrinks with it. Larger scenes keep 1: a step
// proportional to them would move rays near the origin, where their detail usually is, by
// far more than those points' error (RayON's ground is a sphere of radius 1,000).
// Host only: the scene's build computes it once (SceneView::spawn_scale).
inline float spawn_scale_for_extent(float extent) {
  if (!(extent < 2.0f)) return 1.0f;  // NaN too: no geometry, the fixed band
  // extent = m 2^e with m in [0.5, 1), so it lies in [2 scale, 4 scale) for scale 2^(e - 2);
  // tiny extents stop at 2^-100.
  int exponent = 0;
  std::frexp(extent, &exponent);
  return std::ldexp(1.0f, exponent - 2 > -100 ? exponent - 2 : -100);
}

// `normal` must point to the side the new ray leaves towards. Two spawned rays per path
// vertex make this a per-sample cost: on x86 the three axes go through one SSE2 register
// (the same operations lane by lane, so the same bits as the scalar form the device runs).
TESSERA_HD TESSERA_INLINE vec3 offset_ray_origin(const vec3& p, const vec3& normal,
                                                 float spawn_scale = 1.0f) {
  const float origin_band = spawn_scale * kSpawnBand;
  const float near_step = spawn_scale * kSpawnStep;
  constexpr float kIntScale = kSpawnUlps;
#if TESSERA_OFFSET_RAY_SSE2
  const __m128 point = _mm_setr_ps(p.x, p.y, p.z, 0.0f);
  const __m128 n = _mm_setr_ps(normal.x, normal.y, normal.z, 0.0f);
  const __m128i of_i = _mm_cvttps_epi32(_mm_mul_ps(_mm_set1_ps(kIntScale), n));
  // All ones where the coordinate is negative: (x ^ m) - m negates x there.
  const __m128i negative = _mm_castps_si128(_mm_cmplt_ps(point, _mm_setzero_ps()));
  const __m128i step = _mm_sub_epi32(_mm_xor_si128(of_i, negative), negative);
  const __m128 moved = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(point), step));
  const __m128 near_origin =
      _mm_cmplt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), point), _mm_set1_ps(origin_band));
  const __m128 nudged = _mm_add_ps(point, _mm_mul_ps(_mm_set1_ps(near_step), n));
  alignas(16) float out[4];
  _mm_store_ps(out, _mm_or_ps(_mm_and_ps(near_origin, nudged), _mm_andnot_ps(near_origin, moved)));
  return vec3(out[0], out[1], out[2]);
#else
  vec3 result;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int32_t of_i = static_cast<std::int32_t>(kIntScale * normal[axis]);
    // Added as unsigned, which wraps: -0.0f's bits are INT_MIN, and that lane's sum, unused
    // (it is near the origin), would overflow a signed add.
    const auto step = static_cast<std::uint32_t>(p[axis] < 0.0f ? -of_i : of_i);
    const float moved = detail::int_as_float(static_cast<std::int32_t>(
        static_cast<std::uint32_t>(detail::float_as_int(p[axis])) + step));
    result[axis] = std::fabs(p[axis]) < origin_band ? p[axis] + near_step * normal[axis] : moved;
  }
  return result;
#endif
}

}  // namespace tessera
