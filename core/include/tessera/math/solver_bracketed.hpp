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
TESSERA_HD T bracketed_root(const Polynomial<Degree, T>& p, T lo, T hi, T value_lo, T value_hi,
                            T absolute_tolerance) {
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
    const T tolerance = T(2) * kEpsilon * std::fabs(x) + absolute_tolerance;
    if (std::fabs(step) <= tolerance || hi - lo <= tolerance) break;
  }
  return x;
}

}  // namespace detail

// Calls visit(root) for each root of p in [lo, hi], ascending, until it returns true
// (stop: a closest-hit query needs only the first root it accepts, and skipping the
// others saves most of the work). Returns whether the visitor stopped the search. A root
// exactly at a critical point (p == 0 there, a double root) is visited once. The leading
// coefficient should be non-zero; a zero one does no harm, the search finds fewer pieces.
//
// The derivative's roots only separate the pieces, so they are found to a tolerance of
// 1e-10 of the interval rather than to the last bit: a critical point that far off changes
// p there by ~p'' * 1e-20 * length^2, far below its rounding error.
template <int Degree, typename T, typename Visitor>
TESSERA_HD bool visit_roots_in_interval(const Polynomial<Degree, T>& p, T lo, T hi, Visitor&& visit,
                                        T absolute_tolerance = T(0)) {
  static_assert(Degree >= 1, "a constant has no isolated roots");
  if (!(lo <= hi)) return false;
  if constexpr (Degree == 1) {
    if (p.c[1] == T(0)) return false;
    const T x = -p.c[0] / p.c[1];
    return x >= lo && x <= hi && visit(x);
  } else if constexpr (Degree == 2) {
    T r[2];
    const int n = solve_quadratic(p.c[2], p.c[1], p.c[0], r);
    for (int i = 0; i < n; ++i)
      if (r[i] >= lo && r[i] <= hi && visit(r[i])) return true;
    return false;
  } else {
    T critical[Degree - 1];
    int critical_count = 0;
    visit_roots_in_interval(
        p.derivative(), lo, hi,
        [&](T x) {
          critical[critical_count++] = x;
          return critical_count == Degree - 1;
        },
        T(1e-10) * (hi - lo));
    T a = lo;
    T value_a = p(lo);
    T last_visited = hi;
    bool visited_any = false;
    if (value_a == T(0)) {
      if (visit(lo)) return true;
      visited_any = true;
      last_visited = lo;
    }
    for (int i = 0; i <= critical_count; ++i) {
      const T b = i < critical_count ? critical[i] : hi;
      if (!(b > a)) continue;  // repeated critical point
      const T value_b = p(b);
      if (value_b == T(0)) {
        if (!visited_any || last_visited != b) {
          if (visit(b)) return true;
          visited_any = true;
          last_visited = b;
        }
      } else if (value_a != T(0) && ((value_a < T(0)) != (value_b < T(0)))) {
        if (visit(detail::bracketed_root(p, a, b, value_a, value_b, absolute_tolerance)))
          return true;
        visited_any = true;
        last_visited = b;  // not a root, but no later root can equal it either
      }
      a = b;
      value_a = value_b;
    }
    return false;
  }
}

// Roots of p in [lo, hi], ascending, written to roots (room for Degree values); returns
// how many.
template <int Degree, typename T>
TESSERA_HD int roots_in_interval(const Polynomial<Degree, T>& p, T lo, T hi, T* roots) {
  int count = 0;
  visit_roots_in_interval(p, lo, hi, [&](T x) {
    roots[count++] = x;
    return count == Degree;
  });
  return count;
}

}  // namespace tessera
