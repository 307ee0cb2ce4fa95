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

// How far offset_ray_origin moves a coordinate when the hit point's error is not known (the
// shapes that compute their point in double from their own definition): kSpawnUlps units in
// the last place along the normal (times its component), or, within kSpawnBand of zero,
// where ulps vanish, a fixed kSpawnStep: Wächter and Binder's constants, the band and step
// times `spawn_scale` (below). Triangles and quads pass their error bound instead (the
// overload further down): at 1,000 units 256 ulps are 1.5 cm, and RayON's colour-bleed box
// moved there lost the ceiling's light through its 1 cm slit (1.06% dark), while fewer ulps
// let a ground triangle 18 km across hit itself near the origin (0.7% dark), because a
// point's error is a few roundings of the coordinates it was computed from, not of its own.
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

// Relative rounding of one float operation (2^-24), the unit the error bounds below count in.
inline constexpr float kFloatRounding = 0x1p-24f;

// A point computed in float from coordinates no larger than `magnitude` (a hit point from its
// primitive's corners) is within this many roundings of `magnitude` of the exact point on
// the primitive, on every axis. pbrt's bound for a triangle's barycentric point is 7
// (gamma(7)); the spawned ray's own intersection test then rounds its corners against its
// origin at the same magnitude again. The factor is measured, not derived: the stress
// suite's spawn rows (tests/stress/stress_cases.cpp: triangles and quads 1e-3 to 1e4
// across, at the origin and 10 to 1e5 units from it) find self-intersections at 2 (2 of
// 11,548 rays from triangles 1e-3 across) and 0.5, none at 4 with ten times the rays. 8
// keeps a factor of two over that and stays below the detail of RayON's colour-bleed box
// shrunk to 5 mm and moved 10 units out (its light's 10-micrometre slit is 10 ulps there,
// and 32 closed it: 1.4% dark).
inline constexpr float kSpawnErrorRoundings = 8.0f;

// The error bound of a point computed from coordinates of at most `magnitude`.
TESSERA_HD TESSERA_INLINE float position_error_bound(float magnitude) {
  return kSpawnErrorRoundings * kFloatRounding * magnitude;
}

// Moves `p` off its surface along `normal` (unit, to the side the new ray leaves towards) by
// more than `position_error`, a bound on each coordinate's absolute error
// (SurfaceInteraction::position_error): the distance the error can reach along the normal,
// then one more ulp outward on every axis, so the sum's rounding cannot pull the point back.
// Unlike Wächter and Binder's ulps of the point itself, the offset follows the magnitude the
// point was computed from, so it stays small for detail far from the origin (1,000 units
// out, ulps of the point are 1.5 cm) and large enough for a point near the origin on a
// primitive kilometres across. A negative error (not known) takes the ulps (above).
TESSERA_HD TESSERA_INLINE vec3 offset_ray_origin(const vec3& p, const vec3& normal,
                                                 float spawn_scale, float position_error) {
  if (!(position_error >= 0.0f)) return offset_ray_origin(p, normal, spawn_scale);
  const float distance =
      position_error * (std::fabs(normal.x) + std::fabs(normal.y) + std::fabs(normal.z));
  // Then one ulp further in the normal's direction: +1 on the bits where the coordinate's
  // sign matches the normal's (away from zero), -1 where it does not (towards zero); a zero
  // coordinate becomes the smallest subnormal on the normal's side, and an axis the normal
  // does not move stays. On x86 the three axes go through one SSE2 register, the same
  // operations lane by lane as the per-axis form.
#if TESSERA_OFFSET_RAY_SSE2
  const __m128 n = _mm_setr_ps(normal.x, normal.y, normal.z, 0.0f);
  const __m128 moved =
      _mm_add_ps(_mm_setr_ps(p.x, p.y, p.z, 0.0f), _mm_mul_ps(_mm_set1_ps(distance), n));
  const __m128 zero = _mm_setzero_ps();
  const __m128i differ =
      _mm_castps_si128(_mm_xor_ps(_mm_cmplt_ps(moved, zero), _mm_cmplt_ps(n, zero)));
  const __m128i step = _mm_or_si128(differ, _mm_set1_epi32(1));  // -1 where signs differ
  const __m128 stepped = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(moved), step));
  const __m128 smallest =  // copysign(2^-149, n)
      _mm_or_ps(_mm_and_ps(n, _mm_set1_ps(-0.0f)), _mm_castsi128_ps(_mm_set1_epi32(1)));
  const __m128 at_zero = _mm_cmpeq_ps(moved, zero);
  __m128 result = _mm_or_ps(_mm_and_ps(at_zero, smallest), _mm_andnot_ps(at_zero, stepped));
  const __m128 still = _mm_cmpeq_ps(n, zero);
  result = _mm_or_ps(_mm_and_ps(still, moved), _mm_andnot_ps(still, result));
  alignas(16) float out[4];
  _mm_store_ps(out, result);
  return vec3(out[0], out[1], out[2]);
#else
  vec3 moved = p + distance * normal;
  for (int axis = 0; axis < 3; ++axis) {
    const float n = normal[axis];
    const float x = moved[axis];
    if (n == 0.0f) continue;
    if (x == 0.0f) {
      moved[axis] = n > 0.0f ? 0x1p-149f : -0x1p-149f;
      continue;
    }
    const std::int32_t bits = detail::float_as_int(x);
    moved[axis] = detail::int_as_float((x < 0.0f) != (n < 0.0f) ? bits - 1 : bits + 1);
  }
  return moved;
#endif
}

}  // namespace tessera
