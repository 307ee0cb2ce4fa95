#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

// One rational bicubic Bézier piece of a B-spline/NURBS patch, cut out of the patch by
// knot insertion when the scene is built (spline_patch_build.hpp). Plain data of fixed
// size: the per-ray code reads it through a pointer into a flat pool and never allocates.
// Control points are kept in Cartesian form with their weights (not premultiplied), so
// that the ray code can subtract the ray origin before anything else (origins far away
// keep their digits); the homogeneous point of control point (i, j) is (w P, w).
struct RationalBezierPatch {
  dvec3 point[4][4];    // [i along u][j along v]
  double weight[4][4];  // > 0
  // The piece covers [u0, u1] x [v0, v1] of the patch's own parameters; the local Bézier
  // parameters (s, t) in [0, 1]^2 map linearly onto it.
  double u0, u1, v0, v1;
  // Halvings in each direction after which a sub-patch is flat enough that Newton started
  // from its centre converges to the one root it may hold (see flatness_levels).
  std::uint32_t levels_u, levels_v;
  // Box of the control points (holds the piece: the convex hull property, weights > 0).
  dvec3 lower, upper;
};

// Cubic Bernstein basis and its derivative at x.
TESSERA_HD TESSERA_INLINE void bernstein3(double x, double b[4], double db[4]) {
  const double y = 1.0 - x;
  b[0] = y * y * y;
  b[1] = 3.0 * x * y * y;
  b[2] = 3.0 * x * x * y;
  b[3] = x * x * x;
  db[0] = -3.0 * y * y;
  db[1] = 3.0 * y * (y - 2.0 * x);
  db[2] = 3.0 * x * (2.0 * y - x);
  db[3] = 3.0 * x * x;
}

// Point and first partial derivatives of the rational surface at local (s, t), with every
// control point taken relative to `origin` first (the ray origin, or the piece itself).
struct PatchPoint {
  dvec3 position;  // relative to the origin passed in
  dvec3 du, dv;    // derivatives with respect to the local parameters s and t
};

TESSERA_HD TESSERA_INLINE PatchPoint evaluate(const RationalBezierPatch& p, double s, double t,
                                              const dvec3& origin) {
  double bs[4], dbs[4], bt[4], dbt[4];
  bernstein3(s, bs, dbs);
  bernstein3(t, bt, dbt);
  dvec3 h(0.0), hs(0.0), ht(0.0);
  double w = 0.0, ws = 0.0, wt = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double weight = p.weight[i][j];
      const dvec3 wp = (p.point[i][j] - origin) * weight;
      const double b = bs[i] * bt[j], b_s = dbs[i] * bt[j], b_t = bs[i] * dbt[j];
      h += b * wp;
      hs += b_s * wp;
      ht += b_t * wp;
      w += b * weight;
      ws += b_s * weight;
      wt += b_t * weight;
    }
  }
  PatchPoint out;
  out.position = h / w;
  // Quotient rule on the homogeneous form: S' = (H' - S W') / W.
  out.du = (hs - out.position * ws) / w;
  out.dv = (ht - out.position * wt) / w;
  return out;
}

// Number of halvings of a direction after which each sub-patch deviates from its bilinear
// interpolant by at most 5% of its own extent. For a cubic the deviation of the control
// polygon from its chord is at most (3 * 2 / 8) max |second difference| and each halving
// divides the second differences by 4 and the extent by 2 (Filip, Magedson and Markot 1986),
// so k halvings are needed with 2^k >= 0.75 M / (0.05 extent) = 15 M / extent. The
// weights enter through the spread of the Cartesian control points only: a heuristic for
// strongly varying weights, which only shifts work between subdivision and Newton (both
// find every root; see spline_patch.hpp).
inline constexpr std::uint32_t kMaxPatchLevels = 8;

TESSERA_HD TESSERA_INLINE std::uint32_t levels_for(double second_difference, double extent) {
  if (!(extent > 0.0) || !(second_difference > 0.0)) return 0;
  const double ratio = 3.75 * second_difference / extent;
  std::uint32_t k = 0;
  double reach = 1.0;
  while (reach < ratio && k < kMaxPatchLevels) {
    reach *= 2.0;
    ++k;
  }
  return k;
}

TESSERA_HD TESSERA_INLINE void flatness_levels(RationalBezierPatch& p) {
  double second_u = 0.0, second_v = 0.0;
  dvec3 lower(p.point[0][0]), upper(p.point[0][0]);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      lower = glm::min(lower, p.point[i][j]);
      upper = glm::max(upper, p.point[i][j]);
      if (i >= 1 && i <= 2)
        second_u = glm::max(
            second_u, glm::length(p.point[i + 1][j] - 2.0 * p.point[i][j] + p.point[i - 1][j]));
      if (j >= 1 && j <= 2)
        second_v = glm::max(
            second_v, glm::length(p.point[i][j + 1] - 2.0 * p.point[i][j] + p.point[i][j - 1]));
    }
  }
  const double extent = glm::length(upper - lower);
  p.levels_u = levels_for(second_u, extent);
  p.levels_v = levels_for(second_v, extent);
}

// Box of the control points (the convex hull property holds for positive weights).
TESSERA_HD TESSERA_INLINE void control_box(const RationalBezierPatch& p, dvec3& lower,
                                           dvec3& upper) {
  lower = upper = p.point[0][0];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      lower = glm::min(lower, p.point[i][j]);
      upper = glm::max(upper, p.point[i][j]);
    }
}

}  // namespace tessera
