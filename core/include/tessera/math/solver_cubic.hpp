#pragma once
#include <cmath>

#include "tessera/math/polynomial.hpp"
#include "tessera/math/solver_quadratic.hpp"

namespace tessera {

namespace detail {

// Largest-magnitude real root of the depressed cubic y^3 + p y + q. Written as in
// Orellana and De Michele (ACM TOMS Algorithm 1010, sec. 2.2): with Q = -p/3, R = q/2 the
// test R^2 < Q^3 (three real roots) and the Cardano radicand are formed from ratios, so
// neither Q^3 nor R^2 is ever computed and large coefficients do not overflow.
template <typename T>
TESSERA_HD T dominant_root_depressed_cubic(T p, T q) {
  const T Q = -p / T(3);
  const T R = q / T(2);
  if (R == T(0)) return p <= T(0) ? std::sqrt(-p) : T(0);
  const T abs_Q = std::fabs(Q);
  const T abs_R = std::fabs(R);
  // k < 0 exactly when R^2 < Q^3, i.e. when all three roots are real.
  T k;
  if (abs_Q < abs_R) {
    const T ratio = Q / R;
    k = T(1) - Q * ratio * ratio;
  } else {
    const T ratio = R / Q;
    k = (Q > T(0) ? T(1) : T(-1)) * (ratio * ratio / Q - T(1));
  }
  T y;
  if (k < T(0)) {
    const T root_Q = std::sqrt(Q);
    T cos_theta = (R / abs_Q) / root_Q;
    cos_theta = cos_theta > T(1) ? T(1) : (cos_theta < T(-1) ? T(-1) : cos_theta);
    const T theta = std::acos(cos_theta);
    constexpr T kHalfPi = T(1.57079632679489661923);
    constexpr T kTwoPi = T(6.28318530717958647692);
    // Of -2 sqrt(Q) cos((theta + 2 pi j) / 3), j = 0 has the largest magnitude when
    // theta < pi/2 and j = 1 otherwise.
    y = theta < kHalfPi ? T(-2) * root_Q * std::cos(theta / T(3))
                        : T(-2) * root_Q * std::cos((theta + kTwoPi) / T(3));
  } else {
    const T radicand = abs_Q < abs_R ? abs_R * (T(1) + std::sqrt(k))
                                     : abs_R + abs_Q * std::sqrt(abs_Q) * std::sqrt(k);
    const T a = (R > T(0) ? T(-1) : T(1)) * std::cbrt(radicand);
    y = a == T(0) ? T(0) : a + Q / a;
  }
  // The closed form loses digits near multiple roots; Newton restores them where the
  // root is simple and stops as soon as a step fails to reduce the residual.
  const Polynomial<3, T> depressed{{q, p, T(0), T(1)}};
  return polish_root(depressed, y, 8);
}

// Exponent e of the power-of-two scale x = 2^e y that makes a monic cubic's or quartic's
// coefficients O(1) (d = 0 for a cubic): scaling by a power of two changes no digit, and
// keeps the closed forms and the quartic's Newton system finite for roots of any
// magnitude. The coefficients are scaled one by one with ldexp (a / 2^e, b / 2^2e, ...),
// never through 2^4e itself: that overflows to inf (and underflows to 0) once |e| > 256,
// which before silently zeroed the lower coefficients of quartics with a root beyond ~1e77.
template <typename T>
TESSERA_HD int root_scale_exponent(T a, T b, T c, T d = T(0)) {
  T m = std::fabs(a);
  m = std::fmax(m, std::sqrt(std::fabs(b)));
  m = std::fmax(m, std::cbrt(std::fabs(c)));
  m = std::fmax(m, std::sqrt(std::sqrt(std::fabs(d))));
  if (!(m > T(0)) || !std::isfinite(m)) return 0;
  int exponent;
  std::frexp(m, &exponent);
  return exponent;
}

}  // namespace detail

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 = 0, ascending; returns how many (0 to 3,
// multiple roots repeated). One root, the largest in magnitude, comes from the closed form
// on the depressed cubic and is polished with Newton; the other two come from the deflated
// quadratic (whichever of forward or backward deflation leaves the smaller residual, as in
// ACM TOMS Algorithm 954, Flocke 2015) and are polished the same way. c3 == 0 (or so small
// that the monic form overflows) degrades to the quadratic.
//
// The dominant root is found on the cubic scaled by a power of two (x = 2^e y), where the
// depressed form cannot overflow: unscaled, a root of 1e160 made shift^3 infinite and the
// solver returned NaN, and roots 1e-150, 1 and 1e150 came back as one infinite root. The
// scaled cubic may lose its tiny coefficients to underflow, which moves the dominant root
// by nothing representable; the deflation uses the unscaled ones, and its backward form
// ((C - b) / x0 and -c / x0) keeps the small roots' digits beside a huge one, where
// forward deflation (a + x0) cancels them away.
template <typename T>
TESSERA_HD int solve_cubic(T c3, T c2, T c1, T c0, T roots[3]) {
  if (c3 == T(0)) return solve_quadratic(c2, c1, c0, roots);
  const T a = c2 / c3;
  const T b = c1 / c3;
  const T c = c0 / c3;
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c))
    return solve_quadratic(c2, c1, c0, roots);
  const Polynomial<3, T> monic{{c, b, a, T(1)}};

  const int exponent = detail::root_scale_exponent(a, b, c);
  const T as = std::ldexp(a, -exponent);
  const T bs = std::ldexp(b, -2 * exponent);
  const T cs = std::ldexp(c, -3 * exponent);
  const Polynomial<3, T> scaled{{cs, bs, as, T(1)}};
  const T shift = as / T(3);
  const T p = bs - as * shift;
  const T q = (T(2) * shift * shift - bs) * shift + cs;  // 2a^3/27 - ab/3 + c
  T y0 = detail::dominant_root_depressed_cubic(p, q) - shift;
  y0 = polish_root(scaled, y0, 8);
  const T x0 = std::ldexp(y0, exponent);

  // x^3 + a x^2 + b x + c = (x - x0)(x^2 + B x + C): a = B - x0, b = C - x0 B, c = -x0 C.
  // B forward with C forward or backward, whichever reproduces b and c better; then B and
  // C both backward if that reproduces all three better still (a root far larger than the
  // others, where a + x0 cancels their digits).
  T B = a + x0;
  T C = b + x0 * B;
  if (x0 != T(0)) {
    const T C_backward = -c / x0;
    const T residual_forward = std::fabs(x0 * C + c) + std::fabs(C - x0 * B - b);
    const T residual_mixed = std::fabs(x0 * C_backward + c) + std::fabs(C_backward - x0 * B - b);
    if (residual_mixed < residual_forward) C = C_backward;
    const T B_backward = (C_backward - b) / x0;
    const auto residual = [&](T B_try, T C_try) {
      return std::fabs(B_try - x0 - a) + std::fabs(C_try - x0 * B_try - b) +
             std::fabs(x0 * C_try + c);
    };
    if (residual(B_backward, C_backward) < residual(B, C)) {
      B = B_backward;
      C = C_backward;
    }
  }
  T quadratic_roots[2];
  const int n = solve_quadratic(T(1), B, C, quadratic_roots);
  int count = 0;
  roots[count++] = x0;
  for (int i = 0; i < n; ++i) roots[count++] = polish_root(monic, quadratic_roots[i], 4);
  sort_ascending(roots, count);
  return count;
}

}  // namespace tessera
