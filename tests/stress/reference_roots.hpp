#pragma once
// Real roots of a polynomial of degree <= 4 inside [lo, hi], in quad precision, for the
// reference intersectors. Written independently of the production solvers: isolation by
// the roots of the derivative (recursively), then the Illinois variant of regula falsi on
// each bracket down to the last bits, so every root with a sign change is found and none
// is invented. A zero value at a critical point is a multiple root and reported once.
#include "quad_precision.hpp"

namespace tessera::stress {

// p(x) with coefficients c[0..degree], c[i] multiplying x^i.
inline quad evaluate(const quad* c, int degree, quad x) {
  quad v = c[degree];
  for (int i = degree - 1; i >= 0; --i) v = v * x + c[i];
  return v;
}

inline quad illinois(const quad* c, int degree, quad a, quad b, quad fa, quad fb) {
  int side = 0;
  for (int i = 0; i < 400; ++i) {
    const quad x = (a * fb - b * fa) / (fb - fa);
    if (!(x > a && x < b)) break;
    const quad fx = evaluate(c, degree, x);
    if (fx == 0) return x;
    if ((fx < 0) == (fa < 0)) {
      a = x;
      fa = fx;
      if (side == -1) fb /= 2;
      side = -1;
    } else {
      b = x;
      fb = fx;
      if (side == 1) fa /= 2;
      side = 1;
    }
    if (b - a <= quad(1e-32) * (qabs(a) + qabs(b))) break;
  }
  return (a + b) / 2;
}

inline int reference_roots(const quad* c, int degree, quad lo, quad hi, quad* out) {
  while (degree > 0 && c[degree] == 0) --degree;
  if (degree <= 0) return 0;
  if (degree == 1) {
    const quad x = -c[0] / c[1];
    if (x >= lo && x <= hi) {
      out[0] = x;
      return 1;
    }
    return 0;
  }
  quad derivative[4];
  for (int i = 1; i <= degree; ++i) derivative[i - 1] = quad(i) * c[i];
  quad critical[4];
  const int nc = reference_roots(derivative, degree - 1, lo, hi, critical);
  quad points[6];
  int np = 0;
  points[np++] = lo;
  for (int i = 0; i < nc; ++i)
    if (critical[i] > points[np - 1]) points[np++] = critical[i];
  if (hi > points[np - 1]) points[np++] = hi;
  int n = 0;
  quad fa = evaluate(c, degree, points[0]);
  if (fa == 0) out[n++] = points[0];
  for (int i = 1; i < np; ++i) {
    const quad fb = evaluate(c, degree, points[i]);
    if (fb == 0) {
      out[n++] = points[i];
    } else if (fa != 0 && ((fa < 0) != (fb < 0))) {
      out[n++] = illinois(c, degree, points[i - 1], points[i], fa, fb);
    }
    fa = fb;
  }
  return n;
}

}  // namespace tessera::stress
