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
// where a sign change was observed, and the signs at the pieces' ends are ones the
// evaluation can vouch for (sign_reliable_value), so no root is invented; every simple
// root whose neighbourhood values exceed the evaluation error is found, and to full
// precision. What it cannot tell apart is a double root from a near-double one whose
// extremum is below even the compensated evaluation's error (an exactly tangent ray):
// it reports the critical point as a root.

// How a root search ended.
enum class RootSearch {
  kCompleted,     // every root in the interval was visited
  kStopped,       // the visitor returned true
  kNotConverged,  // a root (or a critical point separating roots) did not converge: the
                  // roots visited before it are right, the search stopped there
};

// How a search treats intervals that span many orders of magnitude.
enum class RootSpan {
  // Ray intervals, already bounded by the shape: the critical points that separate roots
  // are found to 1e-10 of the interval, and brackets are halved arithmetically.
  kBounded,
  // Any interval, up to Cauchy's bound of any polynomial (the public solver): critical
  // points to full precision, and a bracket spanning orders of magnitude is halved in
  // its exponent. Roots near 1 beside one near 1e200 then keep their separating critical
  // points (to 1e-10 of the interval they were ~1e190 off, and those roots were lost).
  kAnyMagnitude,
};

namespace detail {

// A lower bound on the magnitude of p's non-zero roots: Cauchy's bound of the reversed
// polynomial, |x| >= |c_k| / (|c_k| + max_{i>k} |c_i|) with c_k the lowest non-zero
// coefficient (a few ulps smaller for its own rounding). Zero when it underflows.
template <int Degree, typename T>
TESSERA_HD T smallest_root_bound(const Polynomial<Degree, T>& p) {
  int lowest = 0;
  while (lowest < Degree && p.c[lowest] == T(0)) ++lowest;
  if (lowest == Degree) return T(0);
  T largest = T(0);
  for (int i = lowest + 1; i <= Degree; ++i) largest = std::fmax(largest, std::fabs(p.c[i]));
  const T bound = T(1) / (T(1) + largest / std::fabs(p.c[lowest]));
  return std::isfinite(bound) ? bound * (T(1) - T(8) * std::numeric_limits<T>::epsilon()) : T(0);
}

// The smaller end of [lo, hi] in magnitude, where magnitudes below smallest_root (no root
// lies there) count as smallest_root, and a bracket that straddles zero has 0.
template <typename T>
TESSERA_HD TESSERA_INLINE T smaller_magnitude(T lo, T hi, T smallest_root) {
  const T floor = std::fmax(smallest_root, std::numeric_limits<T>::min());
  return lo < T(0) && hi > T(0) ? floor : std::fmax(std::fmin(std::fabs(lo), std::fabs(hi)), floor);
}

// Whether [lo, hi] spans orders of magnitude where roots can be (its larger end more than
// 16 times its smaller_magnitude), which arithmetic halving narrows only slowly in relative
// terms (from 1e300 down to 1, ~1000 halvings).
template <typename T>
TESSERA_HD TESSERA_INLINE bool spans_magnitudes(T lo, T hi, T smallest_root) {
  return std::fmax(std::fabs(lo), std::fabs(hi)) > T(16) * smaller_magnitude(lo, hi, smallest_root);
}

// The point that halves [lo, hi] in its exponent where it spans orders of magnitude: zero
// when it straddles zero, else the geometric mean of its larger end and its
// smaller_magnitude; the midpoint otherwise. ~10 halvings from 1e300 to 1 instead of ~1000.
template <typename T>
TESSERA_HD T magnitude_midpoint(T lo, T hi, T smallest_root) {
  const T small = smaller_magnitude(lo, hi, smallest_root);
  const T large = std::fmax(std::fabs(lo), std::fabs(hi));
  if (!(large > T(16) * small)) return T(0.5) * lo + T(0.5) * hi;
  if (lo < T(0) && hi > T(0)) return T(0);
  const T mean = std::sqrt(small) * std::sqrt(large);  // their product may overflow
  return hi > T(0) ? mean : -mean;
}

// Iterations of bracketed_root before it gives up. Newton converges in a handful and
// bisection gains a bit per step, so this is only reached when the bracket spans many
// orders of magnitude under RootSpan::kBounded (e.g. [0, 1e300] around a root near 1,
// where p(hi) overflows and Newton creeps down by a constant factor per step).
inline constexpr int kMaxBracketIterations = 100;

// Root of p in [lo, hi], given p(lo) = value_lo with sign opposite to p(hi) (rtsafe:
// Newton where it converges, bisection where it would leave the bracket or stall).
// Returns false, instead of an unconverged value, when kMaxBracketIterations pass without
// the step or the bracket falling below the tolerance; `root` then holds the last iterate.
// smallest_root (RootSpan::kAnyMagnitude only): no root of p is smaller in magnitude.
template <RootSpan Span = RootSpan::kBounded, int Degree, typename T>
TESSERA_HD bool bracketed_root(const Polynomial<Degree, T>& p, T lo, T hi, T value_lo, T value_hi,
                               T absolute_tolerance, T& root, T smallest_root = T(0)) {
  const auto halve = [smallest_root](T a, T b) {
    if constexpr (Span == RootSpan::kAnyMagnitude) {
      return magnitude_midpoint(a, b, smallest_root);
    } else {
      return T(0.5) * (a + b);
    }
  };
  const bool lo_negative = value_lo < T(0);
  // Regula falsi starting point: already close when p is nearly linear on the bracket.
  T x = lo + (hi - lo) * (value_lo / (value_lo - value_hi));
  if (!(x > lo && x < hi)) x = halve(lo, hi);
  T previous_step = hi - lo;
  T step = previous_step;
  constexpr T kEpsilon = std::numeric_limits<T>::epsilon();
  for (int iteration = 0; iteration < kMaxBracketIterations; ++iteration) {
    T derivative;
    const T value = p.evaluate(x, derivative);
    if (value == T(0)) {
      root = x;
      return true;
    }
    if ((value < T(0)) == lo_negative) {
      lo = x;
    } else {
      hi = x;
    }
    const T newton = x - value / derivative;
    // Newton's own step below the tolerance: x is the root to that tolerance. Without this
    // test a step below half an ulp left Newton on the bracket's end, which reads as
    // leaving the bracket, and the search bisected away from the root it had and crept
    // back one halving at a time (~50 more evaluations).
    if (std::fabs(newton - x) <= T(2) * kEpsilon * std::fabs(x) + absolute_tolerance) {
      root = x;
      return true;
    }
    T next;
    // Bisect when Newton leaves the bracket (or is not finite, which the comparisons also
    // catch) or when it is not halving the step size fast enough.
    bool bisect = !(newton > lo && newton < hi) ||
                  std::fabs(T(2) * value) > std::fabs(previous_step * derivative);
    if constexpr (Span == RootSpan::kAnyMagnitude) {
      // Far from its roots a polynomial of degree n looks like x^n, and Newton moves by
      // about x / n per step (halving is enough for the test above): from 1e40 towards a
      // root near 1 that is ~130 steps. While the bracket spans orders of magnitude,
      // halve its exponent instead, unless Newton is converging (a step below x / 8).
      if (!bisect && spans_magnitudes(lo, hi, smallest_root) &&
          !(std::fabs(newton - x) < T(0.125) * std::fabs(x)))
        bisect = true;
    }
    if (bisect) {
      previous_step = step;
      next = halve(lo, hi);
    } else {
      previous_step = step;
      next = newton;
    }
    step = next - x;
    x = next;
    const T tolerance = T(2) * kEpsilon * std::fabs(x) + absolute_tolerance;
    if (std::fabs(step) <= tolerance || hi - lo <= tolerance) {
      root = x;
      return true;
    }
  }
  root = x;
  return false;
}

// p(x) where its sign can be trusted, else 0. Horner's running error bound decides almost
// every sign; a value within it (p near a critical point that nearly touches zero: a
// complex pair of roots close to the real axis beside a real root) is evaluated again by
// compensated Horner, as accurate as twice the precision; only a value within that bound
// too comes back as 0, a root there (a double root to that precision). Without this, a
// sign lost in rounding at a critical point made two roots, or removed two. Bounds that
// overflow leave the value as it is (its sign is the best there is).
template <int Degree, typename T>
TESSERA_HD T sign_reliable_value(const Polynomial<Degree, T>& p, T x) {
  T error;
  const T value = p.evaluate_with_error(x, error);
  if (!(std::fabs(value) <= error) || !std::isfinite(error)) return value;
  const T refined = p.evaluate_compensated(x, error);
  if (!(std::fabs(refined) <= error) || !std::isfinite(error)) return refined;
  return T(0);
}

// Cauchy's bound: every root of p lies in (-B, B), B = 1 + max |c_i / c_n| (widened by a
// few ulps for its own rounding). Infinite when the leading coefficient is zero.
template <int Degree, typename T>
TESSERA_HD T cauchy_bound(const Polynomial<Degree, T>& p) {
  if (p.c[Degree] == T(0)) return std::numeric_limits<T>::infinity();
  T largest = T(0);
  for (int i = 0; i < Degree; ++i) largest = std::fmax(largest, std::fabs(p.c[i] / p.c[Degree]));
  return (T(1) + largest) * (T(1) + T(8) * std::numeric_limits<T>::epsilon());
}

// The search itself, without the clip (for callers whose interval is already bounded, as
// the torus's is by its bounding sphere). Forced inline: with the failure checks added,
// GCC stopped inlining the derivative's search into the torus intersector, which cost it
// 4% more instructions (callgrind); inlined, the torus is within 0.5% of before.
template <RootSpan Span = RootSpan::kBounded, int Degree, typename T, typename Visitor>
TESSERA_HD TESSERA_FORCE_INLINE RootSearch visit_roots(const Polynomial<Degree, T>& p, T lo, T hi,
                                                       Visitor&& visit, T absolute_tolerance) {
  static_assert(Degree >= 1, "a constant has no isolated roots");
  if (!(lo <= hi)) return RootSearch::kCompleted;
  if constexpr (Degree == 1) {
    if (p.c[1] == T(0)) return RootSearch::kCompleted;
    const T x = -p.c[0] / p.c[1];
    return x >= lo && x <= hi && visit(x) ? RootSearch::kStopped : RootSearch::kCompleted;
  } else if constexpr (Degree == 2) {
    T r[2];
    const int n = solve_quadratic(p.c[2], p.c[1], p.c[0], r);
    for (int i = 0; i < n; ++i)
      if (r[i] >= lo && r[i] <= hi && visit(r[i])) return RootSearch::kStopped;
    return RootSearch::kCompleted;
  } else {
    T critical[Degree - 1];
    int critical_count = 0;
    // A critical point that did not converge could put two roots in one piece (or none
    // where there is one): nothing found after it could be trusted.
    const T critical_tolerance = Span == RootSpan::kBounded ? T(1e-10) * (hi - lo) : T(0);
    if (visit_roots<Span>(
            p.derivative(), lo, hi,
            [&](T x) {
              critical[critical_count++] = x;
              return critical_count == Degree - 1;
            },
            critical_tolerance) == RootSearch::kNotConverged)
      return RootSearch::kNotConverged;
    T smallest_root = T(0);
    if constexpr (Span == RootSpan::kAnyMagnitude) smallest_root = smallest_root_bound(p);
    T a = lo;
    T value_a = sign_reliable_value(p, lo);
    T last_visited = hi;
    bool visited_any = false;
    if (value_a == T(0)) {
      if (visit(lo)) return RootSearch::kStopped;
      visited_any = true;
      last_visited = lo;
    }
    for (int i = 0; i <= critical_count; ++i) {
      const T b = i < critical_count ? critical[i] : hi;
      if (!(b > a)) continue;  // repeated critical point
      const T value_b = sign_reliable_value(p, b);
      if (value_b == T(0)) {
        if (!visited_any || last_visited != b) {
          if (visit(b)) return RootSearch::kStopped;
          visited_any = true;
          last_visited = b;
        }
      } else if (value_a != T(0) && ((value_a < T(0)) != (value_b < T(0)))) {
        T root;
        if (!bracketed_root<Span>(p, a, b, value_a, value_b, absolute_tolerance, root,
                                  smallest_root))
          return RootSearch::kNotConverged;
        if (visit(root)) return RootSearch::kStopped;
        visited_any = true;
        last_visited = b;  // not a root, but no later root can equal it either
      }
      a = b;
      value_a = value_b;
    }
    return RootSearch::kCompleted;
  }
}

}  // namespace detail

// Calls visit(root) for each root of p in [lo, hi], ascending, until it returns true
// (stop: a closest-hit query needs only the first root it accepts, and skipping the
// others saves most of the work). Returns how the search ended. A root
// exactly at a critical point (p == 0 there, a double root) is visited once. The leading
// coefficient should be non-zero; a zero one does no harm, the search finds fewer pieces.
//
// Where the interval is wide against the smallest root p can have, the search is
// RootSpan::kAnyMagnitude: the derivative's roots, which separate the pieces, are found to
// full precision, and brackets are halved in their exponent where they span orders of
// magnitude, so roots of very different sizes (1, 2, 3 and 1e200) are all found.
// (The torus, whose interval its bounding sphere bounds, calls detail::visit_roots with
// kBounded: critical points to 1e-10 of the interval, which changes p there by
// ~p'' * 1e-20 * length^2, far below its rounding error, in fewer Newton steps.)
template <int Degree, typename T, typename Visitor>
TESSERA_HD RootSearch visit_roots_in_interval(const Polynomial<Degree, T>& p, T lo, T hi,
                                              Visitor&& visit, T absolute_tolerance = T(0)) {
  // Search only where roots can be: the critical points that separate them are found to a
  // fraction of the interval, so an interval far wider than the roots' spread (say
  // [-1e300, 1e300] around roots near 1) would place them ~1e290 off and lose or merge
  // roots without a sign of failure. Clipping cannot drop a root (Cauchy's bound holds
  // every root, and by Gauss-Lucas every critical point); ray intervals are within it.
  const T bound = detail::cauchy_bound(p);
  if (lo < -bound) lo = -bound;
  if (hi > bound) hi = bound;
  // Within three orders of magnitude of the smallest root p can have, the bounded search
  // (critical points to 1e-10 of the interval) separates roots as well and is about 1.5x
  // faster (tessera-bench-geometry's random quartics on [-2, 2]).
  if (hi - lo <= T(1e3) * detail::smallest_root_bound(p))
    return detail::visit_roots<RootSpan::kBounded>(p, lo, hi, visit, absolute_tolerance);
  return detail::visit_roots<RootSpan::kAnyMagnitude>(p, lo, hi, visit, absolute_tolerance);
}

// Roots of p in [lo, hi], ascending, written to roots (room for Degree values); returns
// how many, or kSolverFailed when a root did not converge (see RootSearch).
template <int Degree, typename T>
TESSERA_HD int roots_in_interval(const Polynomial<Degree, T>& p, T lo, T hi, T* roots) {
  int count = 0;
  const RootSearch search = visit_roots_in_interval(p, lo, hi, [&](T x) {
    roots[count++] = x;
    return count == Degree;
  });
  return search == RootSearch::kNotConverged ? kSolverFailed : count;
}

}  // namespace tessera
