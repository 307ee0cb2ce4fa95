#pragma once
#include <cmath>
#include <limits>

#include "tessera/math/polynomial.hpp"
#include "tessera/math/solver_quadratic.hpp"

namespace tessera {

// Real roots of a polynomial inside [lo, hi] by root isolation: the roots of the derivative
// (found the same way, recursively down to the closed-form quadratic) cut the interval into
// pieces on which the polynomial is monotonic, so each piece holds at most one root, and it
// holds one exactly when the signs at its ends differ. Each such root is then found by
// Newton steps kept inside the shrinking bracket (bisection when a step leaves it).
// See Yuksel, "High-Performance Polynomial Root Finding for Graphics" (HPG 2022).
//
// Why this suits ray tracing: only the ray's interval is searched; a root is reported only
// where a sign change was observed, so no root is ever invented; every simple root whose
// neighbourhood values exceed the evaluation error is found, and to full precision. What
// it cannot see is a double root whose extremum value is lost in rounding (an exactly
// tangent ray), which no floating-point method decides reliably either.

namespace detail {

// Root of p in [lo, hi], given p(lo) = value_lo with sign opposite to p(hi) (rtsafe:
// Newton where it converges, bisection where it would leave the bracket or stall).
template <int Degree, typename T>
TESSERA_HD T bracketed_root(const Polynomial<Degree, T>& p, T lo, T hi, T value_lo, T value_hi) {
  const bool lo_negative = value_lo < T(0);
  // Regula falsi starting point: already close when p is nearly linear on the bracket.
  T x = lo + (hi - lo) * (value_lo / (value_lo - value_hi));
  if (!(x > lo && x < hi)) x = T(0.5) * (lo + hi);
  T previous_step = hi - lo;
  T step = previous_step;
  constexpr T kEpsilon = std::numeric_limits<T>::epsilon();
  for (int iteration = 0; iteration < 100; ++iteration) {
    T derivative;
    const T value = p.evaluate(x, derivative);
    if (value == T(0)) return x;
    if ((value < T(0)) == lo_negative) {
      lo = x;
    } else {
      hi = x;
    }
    const T newton = x - value / derivative;
    T next;
    // Bisect when Newton leaves the bracket (or is not finite, which the comparisons also
    // catch) or when it is not halving the step size fast enough.
    if (!(newton > lo && newton < hi) ||
        std::fabs(T(2) * value) > std::fabs(previous_step * derivative)) {
      previous_step = step;
      next = T(0.5) * (lo + hi);
    } else {
      previous_step = step;
      next = newton;
    }
    step = next - x;
    x = next;
    const T tolerance = T(2) * kEpsilon * std::fabs(x);
    if (std::fabs(step) <= tolerance || hi - lo <= tolerance) break;
  }
  return x;
}

}  // namespace detail

// Roots of p in [lo, hi], ascending, written to roots (room for Degree values); returns
// how many. A root exactly at a critical point (p == 0 there, a double root) is reported
// once. The leading coefficient must be non-zero for the degree to be meaningful, but a
// zero one does no harm: the search then simply finds fewer pieces.
template <int Degree, typename T>
TESSERA_HD int roots_in_interval(const Polynomial<Degree, T>& p, T lo, T hi, T* roots) {
  static_assert(Degree >= 1, "a constant has no isolated roots");
  if (!(lo <= hi)) return 0;
  if constexpr (Degree == 1) {
    if (p.c[1] == T(0)) return 0;
    const T x = -p.c[0] / p.c[1];
    if (!(x >= lo && x <= hi)) return 0;
    roots[0] = x;
    return 1;
  } else if constexpr (Degree == 2) {
    T r[2];
    const int n = solve_quadratic(p.c[2], p.c[1], p.c[0], r);
    int count = 0;
    for (int i = 0; i < n; ++i)
      if (r[i] >= lo && r[i] <= hi) roots[count++] = r[i];
    return count;
  } else {
    T critical[Degree - 1];
    const int critical_count = roots_in_interval(p.derivative(), lo, hi, critical);
    int count = 0;
    T a = lo;
    T value_a = p(lo);
    if (value_a == T(0)) roots[count++] = lo;
    for (int i = 0; i <= critical_count; ++i) {
      const T b = i < critical_count ? critical[i] : hi;
      if (!(b > a)) continue;  // repeated critical point
      const T value_b = p(b);
      if (value_b == T(0)) {
        if (count == 0 || roots[count - 1] != b) roots[count++] = b;
      } else if (value_a != T(0) && ((value_a < T(0)) != (value_b < T(0)))) {
        if (count < Degree) roots[count++] = detail::bracketed_root(p, a, b, value_a, value_b);
      }
      a = b;
      value_a = value_b;
      if (count == Degree) break;
    }
    return count;
  }
}

}  // namespace tessera
