#pragma once
#include <cmath>
#include <limits>

#include "tessera/math/error_free.hpp"
#include "tessera/math/host_device.hpp"

namespace tessera {

// A real polynomial c[0] + c[1] x + ... + c[Degree] x^Degree with a fixed degree, so that
// evaluation and root finding unroll and never allocate.
// Returned instead of a root count by solvers that cannot vouch for their answer (a bracket
// that did not converge, coefficients whose scaling lost digits): the caller learns that it
// has no answer, rather than receiving roots that may be wrong. Negative, so loops
// `for (i = 0; i < count; ++i)` over it visit nothing.
inline constexpr int kSolverFailed = -1;

template <int Degree, typename T>
struct Polynomial {
  static_assert(Degree >= 0, "degree must be non-negative");
  T c[Degree + 1];

  TESSERA_HD T operator()(T x) const {
    T value = c[Degree];
    for (int i = Degree - 1; i >= 0; --i) value = value * x + c[i];
    return value;
  }

  // Value and first derivative in one Horner pass.
  TESSERA_HD T evaluate(T x, T& derivative) const {
    T value = c[Degree];
    derivative = T(0);
    for (int i = Degree - 1; i >= 0; --i) {
      derivative = derivative * x + value;
      value = value * x + c[i];
    }
    return value;
  }

  // Value with a rigorous bound on its rounding error (Higham, "Accuracy and Stability of
  // Numerical Algorithms", 2nd ed., eq. 5.7: running error bound of Horner's rule). The
  // bound tells a root finder when a sign is noise rather than information.
  TESSERA_HD T evaluate_with_error(T x, T& error_bound) const {
    T value = c[Degree];
    T mu = std::fabs(value) * T(0.5);
    const T ax = std::fabs(x);
    for (int i = Degree - 1; i >= 0; --i) {
      value = value * x + c[i];
      mu = mu * ax + std::fabs(value);
    }
    constexpr T kUnitRoundoff = std::numeric_limits<T>::epsilon() * T(0.5);
    error_bound = kUnitRoundoff * (T(2) * mu - std::fabs(value));
    return value;
  }

  // Value by compensated Horner (Graillat, Langlois and Louvet, "Compensated Horner
  // scheme", 2005): each step's rounding errors, found exactly by two_product and two_sum,
  // are summed by a second Horner pass and added at the end, so the result is as accurate
  // as Horner's rule at twice the precision, then rounded. `error_bound` bounds its error:
  // u |value| + 2 gamma_2n^2 sum |c_i| |x|^i (their Theorem 3.1, with a factor of 2 for the
  // rounding of the sum itself). For the rare sign a running bound cannot decide.
  TESSERA_HD T evaluate_compensated(T x, T& error_bound) const {
    T value = c[Degree];
    T correction = T(0);
    T magnitude = std::fabs(value);
    const T ax = std::fabs(x);
    for (int i = Degree - 1; i >= 0; --i) {
      T product, product_error, sum, sum_error;
      two_product(value, x, product, product_error);
      two_sum(product, c[i], sum, sum_error);
      correction = correction * x + (product_error + sum_error);
      value = sum;
      magnitude = magnitude * ax + std::fabs(c[i]);
    }
    constexpr T kUnitRoundoff = std::numeric_limits<T>::epsilon() * T(0.5);
    constexpr T kGamma = T(2 * Degree) * kUnitRoundoff / (T(1) - T(2 * Degree) * kUnitRoundoff);
    const T result = value + correction;
    error_bound = kUnitRoundoff * std::fabs(result) + T(2) * kGamma * kGamma * magnitude;
    return result;
  }
  TESSERA_HD Polynomial<(Degree > 0 ? Degree - 1 : 0), T> derivative() const {
    Polynomial<(Degree > 0 ? Degree - 1 : 0), T> d{};
    if constexpr (Degree == 0) {
      d.c[0] = T(0);
    } else {
      for (int i = 1; i <= Degree; ++i) d.c[i - 1] = static_cast<T>(i) * c[i];
    }
    return d;
  }
};

// Newton polishing of an approximate root: steps are taken only while they reduce |p|, so
// a root that is already as accurate as the evaluation allows is never made worse, and a
// zero derivative (a multiple root) stops the iteration instead of producing inf or NaN.
template <int Degree, typename T>
TESSERA_HD T polish_root(const Polynomial<Degree, T>& p, T x, int max_iterations = 4) {
  T derivative;
  T value = p.evaluate(x, derivative);
  for (int i = 0; i < max_iterations && value != T(0); ++i) {
    if (derivative == T(0)) break;
    const T next = x - value / derivative;
    if (!std::isfinite(next)) break;
    T next_derivative;
    const T next_value = p.evaluate(next, next_derivative);
    if (!(std::fabs(next_value) < std::fabs(value))) break;
    x = next;
    value = next_value;
    derivative = next_derivative;
  }
  return x;
}

// Sorts up to a handful of values in place (insertion sort: the counts here are <= 8).
template <typename T>
TESSERA_HD void sort_ascending(T* values, int count) {
  for (int i = 1; i < count; ++i) {
    const T key = values[i];
    int j = i - 1;
    while (j >= 0 && values[j] > key) {
      values[j + 1] = values[j];
      --j;
    }
    values[j + 1] = key;
  }
}

}  // namespace tessera
