#pragma once
// atan2 and sincos for the light samplers' per-sample geometry (spherical rectangles and
// triangles), inline and branch-light: libm's atan2f and sincosf are out-of-line calls that
// cost about 8% of a path-traced sample on a scene lit by one rectangle. Both stay within
// a few float ulps of the exact value (tests/unit/math/fast_trig_test.cpp bounds them), the
// precision the spherical maps already lose to their float angle sums. The float
// polynomials are weighted least-squares fits of atan on [0, 1] and of sin and cos on
// [0, pi/4], made for this file; the azimuth sincos (of 2 pi u) and the double sincos use
// Taylor's coefficients, which are accurate enough at their degrees.
#include <cmath>

#include "tessera/math/host_device.hpp"

namespace tessera {

// atan(t) for t in [0, 1]: t P(t^2), relative error below 2e-8 before rounding. P is
// evaluated by Estrin's scheme (pairs of terms, then pairs of pairs), not Horner's: the
// spherical light samplers wait on this result, and Horner's eight dependent multiply-adds
// were the longest stretch of the rectangle's set-up (perf annotate of the colour-bleed box).
TESSERA_HD TESSERA_INLINE float atan_unit_interval(float t) {
  const float z = t * t;
  const float z2 = z * z;
  const float z4 = z2 * z2;
  const float p01 = 0.99999998f - 0.33333071f * z;
  const float p23 = 0.19992591f - 0.14203467f * z;
  const float p45 = 0.10640382f - 0.075033442f * z;
  const float p67 = 0.042682329f - 0.016063957f * z;
  const float p0123 = p01 + p23 * z2;
  const float p4567 = p45 + p67 * z2;
  const float p = p0123 + (p4567 + 0.0028489192f * z4) * z4;
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

namespace detail {
// sin and cos of r + q pi / 2 from those of r (the reduced argument): a branch on the
// quadrant, which the light samplers' narrow angle ranges keep predictable.
template <typename Real>
TESSERA_HD TESSERA_INLINE void place_in_quadrant(int q, Real s, Real c, Real& sin_x, Real& cos_x) {
  switch (q & 3) {
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
}  // namespace detail

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
  // Estrin's scheme, as in atan_unit_interval: the rectangle sampler's chain waits on it.
  const float z = r * r;
  const float z2 = z * z;
  const float s = r + (r * z) * ((-0.16666650f + 0.0083320120f * z) - 0.00019501357f * z2);
  const float c =
      (1.0f - 0.5f * z) + z2 * ((0.041666617f - 0.0013886614f * z) + 2.4379490e-05f * z2);
  detail::place_in_quadrant(quadrant_index, s, c, sin_x, cos_x);
}

// sin and cos in double for |x| < 1e3 (libm beyond): the rectangle sampler's near-plane
// path needs double's precision (SphericalRectangle::sample_near_plane) and libm's sincos
// was 1.6% of the colour-bleed box's wall clock, whose ceiling is 1 cm above its light.
// Cody and Waite's reduction by pi/2 in two parts (the leading one has 33 significant bits,
// so its product with the quadrant is exact), then Taylor polynomials on [-pi/4, pi/4]
// whose remainders are below 5e-17.
TESSERA_HD TESSERA_INLINE void fast_sincos(double x, double& sin_x, double& cos_x) {
  if (!(std::fabs(x) < 1.0e3)) {
    sin_x = std::sin(x);
    cos_x = std::cos(x);
    return;
  }
  const int quadrant_index = static_cast<int>(x * 0.63661977236758134 + std::copysign(0.5, x));
  const double quadrant = static_cast<double>(quadrant_index);
  const double r = (x - quadrant * 1.5707963267341256) - quadrant * 6.077100506506192e-11;
  const double z = r * r;
  const double z2 = z * z;
  const double z4 = z2 * z2;
  // Estrin's scheme: 1/(2k+1)! and 1/(2k)! with alternating signs.
  const double s = r + (r * z) * ((-1.6666666666666666e-01 + 8.3333333333333332e-03 * z) +
                                  z2 * (-1.9841269841269841e-04 + 2.7557319223985893e-06 * z) +
                                  z4 * ((-2.5052108385441720e-08 + 1.6059043836821613e-10 * z) +
                                        z2 * (-7.6471637318198164e-13)));
  const double c = (1.0 - 0.5 * z) + z2 * (4.1666666666666664e-02 - 1.3888888888888889e-03 * z) +
                   z4 * ((2.4801587301587302e-05 - 2.7557319223985888e-07 * z) +
                         z2 * (2.0876756987868100e-09 - 1.1470745597729725e-11 * z) +
                         z4 * 4.7794773323873853e-14);
  detail::place_in_quadrant(quadrant_index, s, c, sin_x, cos_x);
}

// sin and cos of 2 pi `turns` for turns in [0, 1] (the samplers' azimuths 2 pi u): no
// branch on the quadrant, which such angles take at random (fast_sincos's switch would be
// mispredicted, and libm's sinf and cosf were 3.5% of the colour-bleed box's wall clock).
// The half angle pi w, w = turns - round(turns) in [-1/2, 1/2], gets Taylor polynomials
// good to 2e-7 on [-pi/2, pi/2] (Estrin's scheme), and the double-angle formulas give the
// result. Its absolute error, below 5e-7, is that of rounding 2 pi u to a float first.
TESSERA_HD TESSERA_INLINE void fast_sincos_turns(float turns, float& sin_x, float& cos_x) {
  const float w = turns - static_cast<float>(static_cast<int>(turns + 0.5f));
  const float h = 3.14159265358979324f * w;
  const float z = h * h;
  const float z2 = z * z;
  const float s =
      h + (h * z) * ((-1.0f / 6.0f + (1.0f / 120.0f) * z) +
                     z2 * ((-1.0f / 5040.0f + (1.0f / 362880.0f) * z) - (1.0f / 39916800.0f) * z2));
  const float c =
      (1.0f - 0.5f * z) + z2 * (1.0f / 24.0f - (1.0f / 720.0f) * z) +
      (z2 * z2) * ((1.0f / 40320.0f - (1.0f / 3628800.0f) * z) + (1.0f / 479001600.0f) * z2);
  sin_x = 2.0f * s * c;
  cos_x = (c - s) * (c + s);
}

}  // namespace tessera
