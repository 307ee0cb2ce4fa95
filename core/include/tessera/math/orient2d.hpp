#pragma once
#include <cmath>

#include "tessera/math/error_free.hpp"
#include "tessera/math/host_device.hpp"

namespace tessera {

// Exact sign of the 2D orientation determinant
//   | ax - cx  ay - cy |
//   | bx - cx  by - cy |   > 0: a, b, c counter-clockwise, < 0 clockwise, 0 collinear,
// after Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates" (1997), written from the paper's description: a floating-point filter whose
// error bound is proven there, and, only when the filter cannot decide, the determinant
// summed exactly as a floating-point expansion.
//
// Exactness needs IEEE double with round-to-nearest and products that neither overflow nor
// underflow (|coordinates| between ~1e-146 and ~1e146, or 0): uv coordinates always are.

namespace orient2d_detail {

using tessera::two_product;
using tessera::two_sum;

// Shewchuk's Grow-Expansion: adds q to the non-overlapping expansion e[0..n) (components
// in increasing magnitude) giving n + 1 components, still non-overlapping.
TESSERA_HD TESSERA_INLINE int grow_expansion(double* e, int n, double q) {
  for (int i = 0; i < n; ++i) {
    double sum, error;
    two_sum(q, e[i], sum, error);
    e[i] = error;
    q = sum;
  }
  e[n] = q;
  return n + 1;
}

// Exact sign of ax*by - ax*cy - cx*by - ay*bx + ay*cx + cy*bx, the determinant expanded so
// that no difference is formed before the exact products (the cx*cy terms cancel).
TESSERA_HD TESSERA_INLINE double orient2d_exact(double ax, double ay, double bx, double by,
                                                double cx, double cy) {
  const double factors[6][2] = {{ax, by}, {-ax, cy}, {-cx, by}, {-ay, bx}, {ay, cx}, {cy, bx}};
  double expansion[12];
  int n = 0;
  for (const auto& f : factors) {
    double product, error;
    two_product(f[0], f[1], product, error);
    n = grow_expansion(expansion, n, error);
    n = grow_expansion(expansion, n, product);
  }
  // The most significant non-zero component carries the sign of the exact sum.
  for (int i = n - 1; i >= 0; --i)
    if (expansion[i] != 0.0) return expansion[i];
  return 0.0;
}

}  // namespace orient2d_detail

// Returns a value whose sign is the exact sign of the determinant (its magnitude is the
// determinant's approximation when the filter decided).
TESSERA_HD TESSERA_INLINE double orient2d(double ax, double ay, double bx, double by, double cx,
                                          double cy) {
  const double left = (ax - cx) * (by - cy);
  const double right = (ay - cy) * (bx - cx);
  const double det = left - right;
  // Opposite signs (or a zero): no cancellation, the rounded difference has the exact sign.
  if ((left > 0.0 && right <= 0.0) || (left < 0.0 && right >= 0.0) || (left == 0.0 && right == 0.0))
    return det;
  // Shewchuk's ccwerrboundA = (3 + 16 eps) eps, eps = 2^-53: |det - exact| is below this
  // times |left| + |right|.
  constexpr double kEpsilon = 1.1102230246251565e-16;
  constexpr double kBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
  const double bound = kBound * (std::fabs(left) + std::fabs(right));
  if (det > bound || -det > bound) return det;
  return orient2d_detail::orient2d_exact(ax, ay, bx, by, cx, cy);
}

}  // namespace tessera
