#pragma once
// atan2 and sincos for the light samplers' per-sample geometry (spherical rectangles and
// triangles), inline and branch-light: libm's atan2f and sincosf are out-of-line calls that
// cost about 8% of a path-traced sample on a scene lit by one rectangle. Both stay within
// a few float ulps of the exact value (tests/unit/math/fast_trig_test.cpp bounds them), the
// precision the spherical maps already lose to their float angle sums. The polynomials are
// weighted least-squares fits of atan on [0, 1] and of sin and cos on [0, pi/4], made for
// this file.
#include <cmath>

#include "tessera/math/host_device.hpp"

namespace tessera {

// atan(t) for t in [0, 1]: t P(t^2), relative error below 2e-8 before rounding.
TESSERA_HD TESSERA_INLINE float atan_unit_interval(float t) {
  const float z = t * t;
  float p = 0.0028489192f;
  p = p * z - 0.016063957f;
  p = p * z + 0.042682329f;
  p = p * z - 0.075033442f;
  p = p * z + 0.10640382f;
  p = p * z - 0.14203467f;
  p = p * z + 0.19992591f;
  p = p * z - 0.33333071f;
  p = p * z + 0.99999998f;
  return t * p;
}

// atan2(y, x) in [-pi, pi], with std::atan2's quadrants; 0 for (0, 0). NaN in, NaN out.
TESSERA_HD TESSERA_INLINE float fast_atan2(float y, float x) {
  constexpr float kHalfPi = 1.57079632679489662f;
  constexpr float kPiF = 3.14159265358979324f;
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float larger = ax > ay ? ax : ay;
  const float smaller = ax > ay ? ay : ax;
  if (larger == 0.0f) return std::signbit(x) ? std::copysign(kPiF, y) : y;
  float angle = atan_unit_interval(smaller / larger);
  if (ay > ax) angle = kHalfPi - angle;
  if (std::signbit(x)) angle = kPiF - angle;
  return std::copysign(angle, y);
}

// sin and cos of `x` (the samplers pass angles in [0, 4 pi]): x is reduced by multiples of pi/2
// split in three parts whose leading ones have few enough significant bits that their products with
// the multiple are exact (Cody and Waite), so the reduced argument keeps full precision; then one
// polynomial each on [-pi/4, pi/4].
TESSERA_HD TESSERA_INLINE void fast_sincos(float x, float& sin_x, float& cos_x) {
  constexpr float kTwoOverPi = 0.636619772367581343f;
  constexpr float kHalfPiHigh = 1.5703125f;  // 8 significant bits
  constexpr float kHalfPiMiddle = 4.837512969970703125e-4f;
  constexpr float kHalfPiLow = 7.54978995489188216e-8f;
  // Past the reduction's exact range (and for NaN, whose conversion to int is undefined),
  // libm: never on the samplers' path.
  if (!(std::fabs(x) < 1.0e4f)) {
    sin_x = std::sin(x);
    cos_x = std::cos(x);
    return;
  }
  // Rounded half away from zero by truncation: std::nearbyint is a libm call without SSE4.1.
  const int quadrant_index = static_cast<int>(x * kTwoOverPi + std::copysign(0.5f, x));
  const float quadrant = static_cast<float>(quadrant_index);
  const float r = ((x - quadrant * kHalfPiHigh) - quadrant * kHalfPiMiddle) - quadrant * kHalfPiLow;
  const float z = r * r;
  float s = -0.00019501357f;
  s = s * z + 0.0083320120f;
  s = s * z - 0.16666650f;
  s = r + r * z * s;
  float c = 2.4379490e-05f;
  c = c * z - 0.0013886614f;
  c = c * z + 0.041666617f;
  c = c * z - 0.5f;
  c = c * z + 1.0f;
  switch (quadrant_index & 3) {
    case 0:
      sin_x = s;
      cos_x = c;
      break;
    case 1:
      sin_x = c;
      cos_x = -s;
      break;
    case 2:
      sin_x = -s;
      cos_x = -c;
      break;
    default:
      sin_x = -c;
      cos_x = s;
      break;
  }
}

}  // namespace tessera
