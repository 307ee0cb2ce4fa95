#pragma once
#include <cmath>

#include "tessera/math/host_device.hpp"

namespace tessera {

// Error-free transformations: the rounded result and its exact rounding error, so that
// sums and products can be carried at twice the working precision where a decision needs
// it (orient2d's exact expansion, Polynomial::evaluate_compensated). Exact in IEEE
// arithmetic with round-to-nearest, barring overflow and underflow.

// a + b = x + y exactly, |y| <= ulp(x) / 2 (Knuth's two-sum, no ordering of a and b needed).
template <typename T>
TESSERA_HD TESSERA_INLINE void two_sum(T a, T b, T& x, T& y) {
  x = a + b;
  const T b_virtual = x - a;
  const T a_virtual = x - b_virtual;
  const T b_roundoff = b - b_virtual;
  const T a_roundoff = a - a_virtual;
  y = a_roundoff + b_roundoff;
}

// a * b = x + y exactly: the fused multiply-add computes a * b - x with one rounding, and
// that difference is representable (the role of Dekker's splitting).
template <typename T>
TESSERA_HD TESSERA_INLINE void two_product(T a, T b, T& x, T& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

}  // namespace tessera
