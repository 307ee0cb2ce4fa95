#pragma once
#include <cmath>

#include "tessera/math/host_device.hpp"

namespace tessera {

// b^2 - 4ac without losing the digits that decide between one, two or no real roots.
// Float inputs: every product of two floats is exact in double, so the double result is
// correctly rounded up to one subtraction. Double inputs: Kahan's method ("On the Cost of
// Floating-Point Computation Without Extra-Precise Arithmetic", 2004) recovers the rounding
// errors of both products with fma when the two terms nearly cancel.
TESSERA_HD TESSERA_INLINE double quadratic_discriminant(float a, float b, float c) {
  return static_cast<double>(b) * b - 4.0 * static_cast<double>(a) * c;
}

TESSERA_HD TESSERA_INLINE double quadratic_discriminant(double a, double b, double c) {
  const double bb = b * b;
  const double ac4 = 4.0 * a * c;
  const double d = bb - ac4;
  if (3.0 * std::fabs(d) >= bb + std::fabs(ac4)) return d;  // no heavy cancellation
  const double bb_error = std::fma(b, b, -bb);
  const double ac4_error = std::fma(4.0 * a, c, -ac4);
  return d + (bb_error - ac4_error);
}

// Divides a, b and c by one power of two (the roots stay the same, and no digit changes)
// when the largest is beyond 2^500 or below 2^-500: b^2 overflowed from |b| ~ 1.3e154 (the
// second derivative of (x - 1)(x - 2)(x - 3)(x - 1e200) lost its roots to that), and 4ac
// underflows as early. Coefficients between leave every result bit for bit as before.
template <typename T>
TESSERA_HD TESSERA_INLINE void balance_quadratic(T& a, T& b, T& c) {
  if constexpr (sizeof(T) >= sizeof(double)) {
    const T largest = std::fmax(std::fmax(std::fabs(a), std::fabs(b)), std::fabs(c));
    if (!(largest > T(0x1p500)) && !(largest < T(0x1p-500) && largest > T(0))) return;
    if (!std::isfinite(largest)) return;
    int exponent;
    std::frexp(largest, &exponent);
    a = std::ldexp(a, -exponent);
    b = std::ldexp(b, -exponent);
    c = std::ldexp(c, -exponent);
  }
}

// solve_quadratic (below) for coefficients whose largest magnitude is known to lie within
// [2^-500, 2^500], where b^2 and 4ac neither overflow nor underflow: the cylinder's, from
// scenes whose values are validated to +-1e12. Checking that per ray (balance_quadratic)
// cost its test 6-9% (tessera-bench-geometry's cylinder, alternating runs).
template <typename T>
TESSERA_HD int solve_quadratic_in_range(T a, T b, T c, T roots[2]) {
  if (a == T(0)) {
    if (b == T(0)) return 0;
    const T x = -c / b;
    if (!std::isfinite(x)) return 0;
    roots[0] = x;
    return 1;
  }
  const auto disc = quadratic_discriminant(a, b, c);
  if (disc < 0) return 0;
  const auto root_disc = std::sqrt(disc);
  const auto q = -0.5 * (static_cast<decltype(disc)>(b) + (b >= T(0) ? root_disc : -root_disc));
  T x0, x1;
  if (q == 0) {  // b == 0 and disc == 0, hence c == 0: a double root at zero
    x0 = x1 = T(0);
  } else {
    x0 = static_cast<T>(q / a);
    x1 = static_cast<T>(c / q);
  }
  if (!std::isfinite(x0) || !std::isfinite(x1)) {
    // Overflow from extreme coefficient ratios: keep whichever root is representable.
    int count = 0;
    if (std::isfinite(x0)) roots[count++] = x0;
    if (std::isfinite(x1)) roots[count++] = x1;
    return count;
  }
  if (x0 > x1) {
    const T tmp = x0;
    x0 = x1;
    x1 = tmp;
  }
  roots[0] = x0;
  roots[1] = x1;
  return 2;
}

// Real roots of a x^2 + b x + c = 0 in ascending order; returns how many (0, 1 or 2; a
// double root is returned twice). The root of larger magnitude comes from
// q = -(b + sign(b) sqrt(disc)) / 2 and the other from c / q, so neither is formed as a
// difference of nearly equal numbers (the cancellation that breaks -b +- sqrt(disc)).
// a == 0 degrades to the linear equation; a == b == 0 has no isolated root. Coefficients
// of any magnitude (balance_quadratic).
template <typename T>
TESSERA_HD int solve_quadratic(T a, T b, T c, T roots[2]) {
  balance_quadratic(a, b, c);  // float coefficients cannot overflow the double discriminant
  return solve_quadratic_in_range(a, b, c, roots);
}

}  // namespace tessera
