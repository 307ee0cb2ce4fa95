#pragma once
#include <cmath>
#include <limits>

#include "tessera/math/polynomial.hpp"
#include "tessera/math/solver_bracketed.hpp"
#include "tessera/math/solver_cubic.hpp"

namespace tessera {

// Real roots of a general quartic after Orellana and De Michele, "Algorithm 1010: Boosting
// Efficiency in Solving Quartic Equations with No Compromise in Accuracy" (ACM TOMS 46(2),
// 2020). The monic quartic x^4 + a x^3 + b x^2 + c x + d is written as an LDL^T form whose
// one free parameter phi0 is the dominant root of a cubic, factored into two quadratics
// (x^2 + alpha1 x + beta1)(x^2 + alpha2 x + beta2), and the four factor coefficients are
// refined by Newton's method on the system that equates the product with the quartic.
// Unlike Ferrari's formulas this is backward stable: roots are lost or invented only where
// the quartic itself is ill-conditioned. Only real roots are returned (ray tracing needs
// no others); each is finally polished with Newton on the original quartic.
//
// Clean-room implementation from the paper's equations; deviations: the quartic is scaled by
// an exact power of two first (instead of the paper's retry with a fixed factor on
// overflow), and the 4x4 Newton system is solved by Gaussian elimination.
namespace detail {

template <typename T>
TESSERA_HD TESSERA_INLINE T relative_residual(T value, T reference) {
  return reference == T(0) ? std::fabs(value) : std::fabs((value - reference) / reference);
}

// phi0 of eqs. (79)-(88): the cubic is formed after shifting x to an inflection point of
// the quartic (or by -a/4 when there is none), which keeps its coefficients small.
template <typename T>
TESSERA_HD T quartic_phi0(T a, T b, T c, T d) {
  const T radicand = T(9) * a * a - T(24) * b;
  T s;
  if (radicand > T(0)) {
    const T root = std::sqrt(radicand);
    s = T(-2) * b / (a > T(0) ? T(3) * a + root : T(3) * a - root);
  } else {
    s = -a / T(4);
  }
  const T as = a + T(4) * s;
  const T bs = b + T(3) * s * (a + T(2) * s);
  const T cs = c + s * (T(2) * b + s * (T(3) * a + T(4) * s));
  const T ds = d + s * (c + s * (b + s * (a + s)));
  const T gg = bs * bs / T(9);
  const T hh = as * cs;
  const T g = hh - T(4) * ds - T(3) * gg;
  const T h = (T(8) * ds + hh - T(2) * gg) * bs / T(3) - cs * cs - ds * as * as;
  return dominant_root_depressed_cubic(g, h);
}

template <typename T>
TESSERA_HD T ldlt_residual(T b, T c, T d, T d2, T l1, T l2, T l3) {
  return relative_residual(d2 + l1 * l1 + T(2) * l3, b) +
         relative_residual(T(2) * d2 * l2 + T(2) * l1 * l3, c) +
         relative_residual(d2 * l2 * l2 + l3 * l3, d);
}

template <typename T>
TESSERA_HD T factor_residual(T a, T b, T c, T d, T alpha1, T beta1, T alpha2, T beta2) {
  return relative_residual(beta1 * beta2, d) +
         relative_residual(beta1 * alpha2 + alpha1 * beta2, c) +
         relative_residual(beta1 + alpha1 * alpha2 + beta2, b) +
         relative_residual(alpha1 + alpha2, a);
}

template <typename T>
TESSERA_HD T factor_residual_abc(T a, T b, T c, T alpha1, T beta1, T alpha2, T beta2) {
  return relative_residual(beta1 * alpha2 + alpha1 * beta2, c) +
         relative_residual(beta1 + alpha1 * alpha2 + beta2, b) +
         relative_residual(alpha1 + alpha2, a);
}

// Solves the 4x4 system m x = rhs by Gaussian elimination with partial pivoting; false
// when m is singular.
template <typename T>
TESSERA_HD bool solve_linear4(T m[4][4], T rhs[4], T x[4]) {
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int row = col + 1; row < 4; ++row)
      if (std::fabs(m[row][col]) > std::fabs(m[pivot][col])) pivot = row;
    if (m[pivot][col] == T(0)) return false;
    if (pivot != col) {
      for (int k = 0; k < 4; ++k) {
        const T tmp = m[col][k];
        m[col][k] = m[pivot][k];
        m[pivot][k] = tmp;
      }
      const T tmp = rhs[col];
      rhs[col] = rhs[pivot];
      rhs[pivot] = tmp;
    }
    for (int row = col + 1; row < 4; ++row) {
      const T factor = m[row][col] / m[col][col];
      for (int k = col; k < 4; ++k) m[row][k] -= factor * m[col][k];
      rhs[row] -= factor * rhs[col];
    }
  }
  for (int row = 3; row >= 0; --row) {
    T sum = rhs[row];
    for (int k = row + 1; k < 4; ++k) sum -= m[row][k] * x[k];
    x[row] = sum / m[row][row];
  }
  return true;
}

// Newton refinement of (alpha1, beta1, alpha2, beta2) (sec. 2.3): each step is kept only
// if it lowers the summed relative residual of the four product equations.
template <typename T>
TESSERA_HD void refine_quadratic_factors(T a, T b, T c, T d, T& alpha1, T& beta1, T& alpha2,
                                         T& beta2) {
  T error = factor_residual(a, b, c, d, alpha1, beta1, alpha2, beta2);
  for (int iteration = 0; iteration < 8 && error != T(0); ++iteration) {
    T jacobian[4][4] = {{T(0), beta2, T(0), beta1},
                        {beta2, alpha2, beta1, alpha1},
                        {alpha2, T(1), alpha1, T(1)},
                        {T(1), T(0), T(1), T(0)}};
    T residual[4] = {beta1 * beta2 - d, beta1 * alpha2 + alpha1 * beta2 - c,
                     beta1 + alpha1 * alpha2 + beta2 - b, alpha1 + alpha2 - a};
    T step[4];
    if (!solve_linear4(jacobian, residual, step)) break;
    const T next_alpha1 = alpha1 - step[0];
    const T next_beta1 = beta1 - step[1];
    const T next_alpha2 = alpha2 - step[2];
    const T next_beta2 = beta2 - step[3];
    const T next_error =
        factor_residual(a, b, c, d, next_alpha1, next_beta1, next_alpha2, next_beta2);
    if (!(next_error < error)) break;
    alpha1 = next_alpha1;
    beta1 = next_beta1;
    alpha2 = next_alpha2;
    beta2 = next_beta2;
    error = next_error;
  }
}

// beta1 * beta2 = d: recompute the smaller-magnitude beta from the larger one (eq. 42).
template <typename T>
TESSERA_HD TESSERA_INLINE void balance_betas(T d, T& beta1, T& beta2) {
  if (std::fabs(beta2) < std::fabs(beta1)) {
    beta2 = d / beta1;
  } else if (std::fabs(beta2) > std::fabs(beta1)) {
    beta1 = d / beta2;
  }
}

// value * 2^-shift, and whether it stayed in the normal range (or was 0). A power-of-two
// scale is exact there; below it the value may lose digits, and even where it does not,
// the factorization's products of it do: (x + 2^341)(x + 0.625)(x + 0.21875)(x - 0.15625)
// scales d exactly to -1.5e-311, and Algorithm 1010 then found two of the four roots.
template <typename T>
TESSERA_HD TESSERA_INLINE bool scale_in_normal_range(T& value, int shift) {
  const bool zero = value == T(0);
  value = std::ldexp(value, -shift);
  return zero || std::fabs(value) >= std::numeric_limits<T>::min();
}

}  // namespace detail

// Returns the number of real roots written to `roots` (ascending). Where the roots span more
// orders of magnitude than one power-of-two scaling of double holds (1, 2, 3 and 1e200),
// Algorithm 1010 cannot factor the quartic and root isolation over Cauchy's bound answers
// instead; kSolverFailed only if that does not converge either.
template <typename T>
TESSERA_HD int solve_quartic(T c4, T c3, T c2, T c1, T c0, T roots[4]) {
  if (c4 == T(0)) return solve_cubic(c3, c2, c1, c0, roots);
  T a = c3 / c4;
  T b = c2 / c4;
  T c = c1 / c4;
  T d = c0 / c4;
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c) || !std::isfinite(d))
    return solve_cubic(c3, c2, c1, c0, roots);
  const Polynomial<4, T> original{{d, c, b, a, T(1)}};
  if (d == T(0)) {  // x = 0 is a root: the remaining cubic is exact
    int count = solve_cubic(T(1), a, b, c, roots);
    roots[count++] = T(0);
    sort_ascending(roots, count);
    return count;
  }

  // A coefficient that the scaling takes below the normal range loses digits, and with them
  // the small roots it decides (e.g. (x - 1e200)(x - 1)(x - 2)(x - 3): d / 2^4e underflows):
  // no single scaling holds roots that far apart, and isolation takes over.
  const auto isolate = [&] {
    const T bound = detail::cauchy_bound(original);
    return roots_in_interval(original, -bound, bound, roots);
  };
  const int exponent = detail::root_scale_exponent(a, b, c, d);
  if (!detail::scale_in_normal_range(a, exponent) ||
      !detail::scale_in_normal_range(b, 2 * exponent) ||
      !detail::scale_in_normal_range(c, 3 * exponent) ||
      !detail::scale_in_normal_range(d, 4 * exponent))
    return isolate();

  const T phi0 = detail::quartic_phi0(a, b, c, d);
  if (!std::isfinite(phi0)) return isolate();
  const T l1 = a / T(2);                                    // eq. (16)
  const T l3 = b / T(6) + phi0 / T(2);                      // eq. (18)
  const T del2 = c - a * l3;                                // after eq. (27)
  const T d2_candidate = T(2) * b / T(3) - phi0 - l1 * l1;  // eq. (20)
  const T d3_candidate = d - l3 * l3;                       // eq. (15) with d2 = 0

  // Of the (d2, l2) pairs of eqs. (28) and following, keep the one that best reproduces b,
  // c and d.
  T d2 = T(0), l2 = T(0);
  T best = T(0);
  bool have = false;
  auto consider = [&](T d2_try, T l2_try) {
    const T r = detail::ldlt_residual(b, c, d, d2_try, l1, l2_try, l3);
    if (!have || r < best) {
      have = true;
      best = r;
      d2 = d2_try;
      l2 = l2_try;
    }
  };
  if (d2_candidate != T(0)) consider(d2_candidate, del2 / (T(2) * d2_candidate));
  if (del2 != T(0)) {
    const T l2_try = T(2) * d3_candidate / del2;
    if (l2_try != T(0)) consider(del2 / (T(2) * l2_try), l2_try);
    consider(d2_candidate, l2_try);
  }

  // Case I (d2 < 0): two real quadratic factors; case II (d2 > 0): complex conjugate
  // factors, whose roots are all non-real; case III (d2 ~ 0): factors from d3 instead.
  enum class Factors { kReal, kComplex, kNone };
  Factors primary = Factors::kNone;
  T alpha1 = T(0), beta1 = T(0), alpha2 = T(0), beta2 = T(0);
  T gamma = T(0);
  if (d2 < T(0)) {
    primary = Factors::kReal;
    gamma = std::sqrt(-d2);
    alpha1 = l1 + gamma;
    beta1 = l3 + gamma * l2;
    alpha2 = l1 - gamma;
    beta2 = l3 - gamma * l2;
    detail::balance_betas(d, beta1, beta2);
    // Recompute the smaller alpha from the three product equations (eqs. 47-51) and keep
    // the value that best reproduces a, b and c.
    const bool fix_first = std::fabs(alpha1) < std::fabs(alpha2);
    const T known = fix_first ? alpha2 : alpha1;
    const T beta_known = fix_first ? beta2 : beta1;  // paired with `known`
    const T beta_other = fix_first ? beta1 : beta2;  // paired with the alpha being fixed
    T candidates[3];
    int n = 0;
    if (beta_known != T(0)) candidates[n++] = (c - beta_other * known) / beta_known;
    if (known != T(0)) candidates[n++] = (b - beta1 - beta2) / known;
    candidates[n++] = a - known;
    T best_alpha = candidates[n - 1];
    T best_error = T(0);
    for (int i = 0; i < n; ++i) {
      const T err = fix_first
                        ? detail::factor_residual_abc(a, b, c, candidates[i], beta1, alpha2, beta2)
                        : detail::factor_residual_abc(a, b, c, alpha1, beta1, candidates[i], beta2);
      if (i == 0 || err < best_error) {
        best_error = err;
        best_alpha = candidates[i];
      }
    }
    (fix_first ? alpha1 : alpha2) = best_alpha;
  } else if (d2 > T(0)) {
    primary = Factors::kComplex;
    gamma = std::sqrt(d2);
  }

  constexpr T kEpsilon = std::numeric_limits<T>::epsilon();
  const T d2_scale = std::fmax(std::fmax(std::fabs(T(2) * b / T(3)), std::fabs(phi0)), l1 * l1);
  bool real_factors = primary == Factors::kReal;
  if (primary == Factors::kNone || std::fabs(d2) <= kEpsilon * d2_scale) {
    T error_primary = T(0);
    if (primary == Factors::kReal) {
      error_primary = detail::factor_residual(a, b, c, d, alpha1, beta1, alpha2, beta2);
    } else if (primary == Factors::kComplex) {
      // alpha = l1 +- i gamma, beta = l3 +- i gamma l2: every product is real.
      error_primary = detail::relative_residual(l3 * l3 + gamma * gamma * l2 * l2, d) +
                      detail::relative_residual(T(2) * (l1 * l3 + gamma * gamma * l2), c) +
                      detail::relative_residual(T(2) * l3 + l1 * l1 + gamma * gamma, b) +
                      detail::relative_residual(T(2) * l1, a);
    }
    const T d3 = d - l3 * l3;
    T error_alternative;
    T alt_beta1 = T(0), alt_beta2 = T(0);
    if (d3 <= T(0)) {
      const T root = std::sqrt(-d3);
      alt_beta1 = l3 + root;
      alt_beta2 = l3 - root;
      detail::balance_betas(d, alt_beta1, alt_beta2);
      error_alternative = detail::factor_residual(a, b, c, d, l1, alt_beta1, l1, alt_beta2);
    } else {
      error_alternative = detail::relative_residual(l3 * l3 + d3, d) +
                          detail::relative_residual(T(2) * l1 * l3, c) +
                          detail::relative_residual(T(2) * l3 + l1 * l1, b) +
                          detail::relative_residual(T(2) * l1, a);
    }
    if (primary == Factors::kNone || error_alternative < error_primary) {
      real_factors = d3 <= T(0);
      alpha1 = alpha2 = l1;
      beta1 = alt_beta1;
      beta2 = alt_beta2;
    }
  }
  if (!real_factors) return 0;

  detail::refine_quadratic_factors(a, b, c, d, alpha1, beta1, alpha2, beta2);
  T candidates[4];
  int found = solve_quadratic(T(1), alpha1, beta1, candidates);
  found += solve_quadratic(T(1), alpha2, beta2, candidates + found);
  // Polish on the original quartic, and keep only values that are roots to within its
  // evaluation error: when the roots' magnitudes differ by many orders the small factor
  // can come out with the wrong discriminant sign, and this residual test is what stops
  // such an invented pair (a genuine root polishes down to the rounding noise).
  // Both are done on the scaled quartic (y = x / 2^e), which cannot overflow, and the
  // residual is checked on the original too wherever that is finite (the scaled one may
  // have lost tiny roots to underflow).
  const Polynomial<4, T> scaled{{d, c, b, a, T(1)}};
  int count = 0;
  for (int i = 0; i < found; ++i) {
    const T y = polish_root(scaled, candidates[i], 4);
    T error_bound;
    const T value = scaled.evaluate_with_error(y, error_bound);
    if (!(std::fabs(value) <= T(64) * error_bound)) continue;
    const T x = std::ldexp(y, exponent);
    const T original_value = original.evaluate_with_error(x, error_bound);
    if (std::isfinite(original_value) && std::isfinite(error_bound) &&
        !(std::fabs(original_value) <= T(64) * error_bound))
      continue;
    roots[count++] = x;
  }
  sort_ascending(roots, count);
  return count;
}

}  // namespace tessera
