#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/bezier_patch.hpp"
#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// A bicubic B-spline or NURBS patch, as the ray code sees it: a run of rational Bézier
// pieces in a flat pool (built once by build_spline_patch, spline_patch_build.hpp) and the
// patch's parameter domain. HitRecord::u/v and SurfaceInteraction::uv are the patch's own
// parameters (in the knot vectors' units).
struct SplinePatch {
  const RationalBezierPatch* pieces;  // pool.data() + first_piece (rebind after a copy/upload)
  std::uint32_t first_piece;
  std::uint32_t piece_count;
  double u0, u1, v0, v1;  // domain [knots_u[3], knots_u[nu]] x [knots_v[3], knots_v[nv]]
  double size;            // diagonal of the control points' box
  Aabb box;               // conservative float box of every control point
  std::uint32_t material;
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const SplinePatch& p) {
  return p.box;
}

// Every root of a ray with a patch, each a (t, u, v) of the patch's parameters.
inline constexpr int kMaxPatchRoots = 16;

struct PatchRoots {
  double t[kMaxPatchRoots];
  double u[kMaxPatchRoots];
  double v[kMaxPatchRoots];
  int count = 0;

  // Adds a root unless it is one already found: the same point of the ray (a root on the
  // border of two pieces or sub-patches, or at a collapsed edge where many (u, v) give one
  // point), or the same (u, v) (a tangent root that Newton reached from two sub-patches).
  TESSERA_HD bool add(double root_t, double root_u, double root_v, double t_tolerance,
                      double u_tolerance, double v_tolerance) {
    for (int i = 0; i < count; ++i) {
      const bool same_t = std::fabs(t[i] - root_t) <= t_tolerance;
      const bool same_uv =
          std::fabs(u[i] - root_u) <= u_tolerance && std::fabs(v[i] - root_v) <= v_tolerance;
      if (same_t || (same_uv && std::fabs(t[i] - root_t) <= 1e3 * t_tolerance)) return false;
    }
    if (count >= kMaxPatchRoots) return false;
    t[count] = root_t;
    u[count] = root_u;
    v[count] = root_v;
    ++count;
    return true;
  }
};

namespace detail {

// The ray as the intersection of two planes through it (Kajiya 1982; Martin et al. 2000):
// a surface point lies on the ray when its signed distances to both planes vanish, which
// reduces the ray-patch problem to a 2D root of the projected patch.
struct RayPlanes {
  dvec3 origin;
  dvec3 direction;
  dvec3 n1, n2;         // unit, perpendicular to the direction and to each other
  double inverse_dd;    // 1 / (d . d): t of a point is d . (P - o) / (d . d)
  double t_lo, t_hi;    // the interval searched
  double origin_error;  // of the ray, see PreciseRay

  TESSERA_HD static RayPlanes make(const PreciseRay& ray, double t_lo, double t_hi) {
    RayPlanes r;
    r.origin = ray.origin;
    r.direction = ray.direction;
    const dvec3 n = glm::normalize(ray.direction);
    const double sign = n.z >= 0.0 ? 1.0 : -1.0;  // Duff et al. 2017 basis
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    r.n1 = dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    r.n2 = dvec3(b, sign + n.y * n.y * a, -n.y);
    r.inverse_dd = 1.0 / glm::dot(ray.direction, ray.direction);
    r.t_lo = t_lo;
    r.t_hi = t_hi;
    r.origin_error = ray.origin_error;
    return r;
  }
};

// Sub-patch of the projected piece: per control point (distance to plane 1, distance to
// plane 2, t, 1), each multiplied by the weight, i.e. the homogeneous form of a polynomial
// Bézier patch whose values' convex hull bounds the projection.
struct ProjectedCell {
  double c[4][4][4];  // [i][j][component]
  double s0, s1, t0, t1;
  std::uint32_t level_u, level_v;
};

TESSERA_HD TESSERA_INLINE void split_cell(const ProjectedCell& in, bool along_u, ProjectedCell& low,
                                          ProjectedCell& high) {
  low = in;
  high = in;
  // de Casteljau at 1/2 along each row (along_u: the curves c[0..3][j]).
  for (int line = 0; line < 4; ++line) {
    for (int k = 0; k < 4; ++k) {
      double p[4];
      for (int m = 0; m < 4; ++m) p[m] = along_u ? in.c[m][line][k] : in.c[line][m][k];
      const double p01 = 0.5 * (p[0] + p[1]), p12 = 0.5 * (p[1] + p[2]), p23 = 0.5 * (p[2] + p[3]);
      const double p012 = 0.5 * (p01 + p12), p123 = 0.5 * (p12 + p23);
      const double mid = 0.5 * (p012 + p123);
      const double lo[4] = {p[0], p01, p012, mid};
      const double hi[4] = {mid, p123, p23, p[3]};
      for (int m = 0; m < 4; ++m) {
        (along_u ? low.c[m][line][k] : low.c[line][m][k]) = lo[m];
        (along_u ? high.c[m][line][k] : high.c[line][m][k]) = hi[m];
      }
    }
  }
  if (along_u) {
    const double mid = 0.5 * (in.s0 + in.s1);
    low.s1 = mid;
    high.s0 = mid;
    low.level_u = high.level_u = in.level_u + 1;
  } else {
    const double mid = 0.5 * (in.t0 + in.t1);
    low.t1 = mid;
    high.t0 = mid;
    low.level_v = high.level_v = in.level_v + 1;
  }
}

// Whether the cell may hold a root in [t_lo, t_hi]: the box of the projected control points
// contains the 2D origin and the t range overlaps (each test with a slack for the rounding
// of the projection, so that it only ever keeps too much).
TESSERA_HD TESSERA_INLINE bool cell_may_hit(const ProjectedCell& cell, double t_lo, double t_hi) {
  double lo[2] = {cell.c[0][0][0], cell.c[0][0][1]}, hi[2] = {lo[0], lo[1]};
  double magnitude = 0.0;
  bool before = true, after = true;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double* c = cell.c[i][j];
      for (int k = 0; k < 2; ++k) {
        lo[k] = glm::min(lo[k], c[k]);
        hi[k] = glm::max(hi[k], c[k]);
        magnitude = glm::max(magnitude, std::fabs(c[k]));
      }
      const double slack = 1e-12 * (std::fabs(c[2]) + std::fabs(t_lo * c[3]));
      if (c[2] - t_lo * c[3] >= -slack) before = false;
      if (!(c[2] - t_hi * c[3] > slack)) after = false;
    }
  }
  const double slack = 1e-12 * magnitude;
  if (before || after) return false;
  if (!(lo[0] <= slack && hi[0] >= -slack && lo[1] <= slack && hi[1] >= -slack)) return false;
  // The same test along the diagonals (an octagon around the hull instead of a box):
  // slanted cells whose box holds the origin often do not.
  double sum_lo = kInfinity, sum_hi = -kInfinity, diff_lo = kInfinity, diff_hi = -kInfinity;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double sum = cell.c[i][j][0] + cell.c[i][j][1];
      const double diff = cell.c[i][j][0] - cell.c[i][j][1];
      sum_lo = glm::min(sum_lo, sum);
      sum_hi = glm::max(sum_hi, sum);
      diff_lo = glm::min(diff_lo, diff);
      diff_hi = glm::max(diff_hi, diff);
    }
  }
  return sum_lo <= 2.0 * slack && sum_hi >= -2.0 * slack && diff_lo <= 2.0 * slack &&
         diff_hi >= -2.0 * slack;
}

enum class NewtonStep { kContinue, kConverged, kFailed };

// One step of the 2x2 Newton iteration on the two plane distances (f1, f2) with Jacobian
// [[j11, j12], [j21, j22]] in the piece's local parameters (s, t), shared by both
// iterations below. Converged when the distances are at rounding level (`tolerance`) and a
// further step would not move the point (a double root at a tangent converges only
// linearly: the step test, not the iteration count, ends it), or when the Jacobian is
// singular at a root (a collapsed edge); a root must lie inside the piece.
TESSERA_HD TESSERA_INLINE NewtonStep newton_step(double f1, double f2, double j11, double j12,
                                                 double j21, double j22, double tolerance,
                                                 bool last_iteration, double& s, double& t) {
  const double det = j11 * j22 - j12 * j21;
  const bool small = std::fabs(f1) <= tolerance && std::fabs(f2) <= tolerance;
  const bool inside = s >= -1e-9 && s <= 1.0 + 1e-9 && t >= -1e-9 && t <= 1.0 + 1e-9;
  const bool singular = !(det != 0.0) || !std::isfinite(det);
  double ds = singular ? 0.0 : (-f1 * j22 + f2 * j12) / det;
  double dt = singular ? 0.0 : (-j11 * f2 + j21 * f1) / det;
  if (small && (singular || std::fabs(ds) + std::fabs(dt) < 1e-9 || last_iteration)) {
    if (!inside) return NewtonStep::kFailed;
    s = glm::clamp(s, 0.0, 1.0);
    t = glm::clamp(t, 0.0, 1.0);
    return NewtonStep::kConverged;
  }
  if (singular) return NewtonStep::kFailed;
  // Damped: a step of more than half the piece leaves the basin anyway.
  const double step = glm::max(std::fabs(ds), std::fabs(dt));
  if (step > 0.5) {
    ds *= 0.5 / step;
    dt *= 0.5 / step;
  }
  s += ds;
  t += dt;
  return (s > -0.5 && s < 1.5 && t > -0.5 && t < 1.5) ? NewtonStep::kContinue : NewtonStep::kFailed;
}

// Newton's method on the two plane distances of the rational surface point, in the
// piece's local parameters. Returns true with (s, t) and the point (relative to the ray
// origin) when it converged to a root inside the piece.
TESSERA_HD TESSERA_INLINE bool newton_root(const RationalBezierPatch& piece, const RayPlanes& ray,
                                           double scale, double& s, double& t, dvec3& point) {
  for (int iteration = 0; iteration < 32; ++iteration) {
    const PatchPoint p = evaluate(piece, s, t, ray.origin);
    const double f1 = glm::dot(ray.n1, p.position), f2 = glm::dot(ray.n2, p.position);
    const double j11 = glm::dot(ray.n1, p.du), j12 = glm::dot(ray.n1, p.dv);
    const double j21 = glm::dot(ray.n2, p.du), j22 = glm::dot(ray.n2, p.dv);
    point = p.position;
    // Converged: both distances at the rounding level of the point's coordinates.
    const double tolerance = 1e-13 * scale + 4e-16 * glm::length(p.position);
    const NewtonStep step =
        newton_step(f1, f2, j11, j12, j21, j22, tolerance, iteration == 31, s, t);
    if (step != NewtonStep::kContinue) return step == NewtonStep::kConverged;
  }
  return false;
}

// The same Newton iteration on the piece's projection onto the ray's planes (the
// homogeneous (distance 1, distance 2, t, 1) * w control values of ProjectedCell): three
// bicubic scalars instead of the 3D point, about half the work per step. Returns the root's
// t along the ray.
TESSERA_HD TESSERA_INLINE bool newton_projected(const double (&c)[4][4][4], double scale,
                                                double direction_length, double& s, double& t,
                                                double& root_t) {
  for (int iteration = 0; iteration < 32; ++iteration) {
    double bs[4], dbs[4], bt[4], dbt[4];
    bernstein3(s, bs, dbs);
    bernstein3(t, bt, dbt);
    double v[4] = {0, 0, 0, 0}, vs[4] = {0, 0, 0, 0}, vt[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        const double b = bs[i] * bt[j], b_s = dbs[i] * bt[j], b_t = bs[i] * dbt[j];
        for (int k = 0; k < 4; ++k) {
          v[k] += b * c[i][j][k];
          vs[k] += b_s * c[i][j][k];
          vt[k] += b_t * c[i][j][k];
        }
      }
    }
    const double inverse_w = 1.0 / v[3];
    const double f1 = v[0] * inverse_w, f2 = v[1] * inverse_w;
    root_t = v[2] * inverse_w;
    const double j11 = (vs[0] - f1 * vs[3]) * inverse_w, j12 = (vt[0] - f1 * vt[3]) * inverse_w;
    const double j21 = (vs[1] - f2 * vs[3]) * inverse_w, j22 = (vt[1] - f2 * vt[3]) * inverse_w;
    // Converged: both distances at the rounding level of the point's coordinates relative
    // to the ray origin (|t| |d| along the ray).
    const double tolerance = 1e-13 * scale + 4e-16 * std::fabs(root_t) * direction_length;
    const NewtonStep step =
        newton_step(f1, f2, j11, j12, j21, j22, tolerance, iteration == 31, s, t);
    if (step != NewtonStep::kContinue) return step == NewtonStep::kConverged;
  }
  return false;
}

// Distance from `query` to the surface near the local parameters (s, t): a few Gauss-Newton
// steps of the foot point, clamped to the piece. It can only overestimate the distance to
// the whole surface, which is the safe side for its one use (start-surface roots).
TESSERA_HD TESSERA_INLINE double local_distance(const RationalBezierPatch& piece,
                                                const dvec3& query, double s, double t) {
  double distance = 0.0;
  for (int iteration = 0; iteration < 5; ++iteration) {
    const PatchPoint p = evaluate(piece, s, t, query);
    distance = glm::length(p.position);
    const double a = glm::dot(p.du, p.du), b = glm::dot(p.du, p.dv), c = glm::dot(p.dv, p.dv);
    const double g1 = -glm::dot(p.du, p.position), g2 = -glm::dot(p.dv, p.position);
    const double det = a * c - b * b;
    if (!(det > 0.0) || !std::isfinite(det)) break;
    s = glm::clamp(s + (c * g1 - b * g2) / det, 0.0, 1.0);
    t = glm::clamp(t + (a * g2 - b * g1) / det, 0.0, 1.0);
  }
  return glm::min(distance, glm::length(evaluate(piece, s, t, query).position));
}

// Whether the projected cell can hold at most one root: the gradients of the two plane
// distances (homogeneous form; at a root the gradient of w f is w times that of f) lie in
// boxes bounded by the control-point differences, and when their 2x2 determinant keeps one
// sign over every pair of gradients the map is one-to-one on the (convex) cell. For p != q,
// F(q) - F(p) = (g1 . (q - p), g2 . (q - p)) with g1, g2 mean gradients inside those boxes,
// which vanishes only if g1 and g2 are parallel, i.e. their determinant is 0. (After the
// transversality test of Elber and Kim 2001 for two equations in two unknowns.)
TESSERA_HD TESSERA_INLINE bool single_root_cell(const ProjectedCell& cell) {
  double lo[2][2], hi[2][2];  // [function][s or t]
  for (int f = 0; f < 2; ++f) {
    lo[f][0] = lo[f][1] = kInfinity;
    hi[f][0] = hi[f][1] = -kInfinity;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        if (i < 3) {
          const double d = cell.c[i + 1][j][f] - cell.c[i][j][f];
          lo[f][0] = glm::min(lo[f][0], d);
          hi[f][0] = glm::max(hi[f][0], d);
        }
        if (j < 3) {
          const double d = cell.c[i][j + 1][f] - cell.c[i][j][f];
          lo[f][1] = glm::min(lo[f][1], d);
          hi[f][1] = glm::max(hi[f][1], d);
        }
      }
    }
  }
  const auto product = [](double a_lo, double a_hi, double b_lo, double b_hi, double& p_lo,
                          double& p_hi) {
    const double p[4] = {a_lo * b_lo, a_lo * b_hi, a_hi * b_lo, a_hi * b_hi};
    p_lo = glm::min(glm::min(p[0], p[1]), glm::min(p[2], p[3]));
    p_hi = glm::max(glm::max(p[0], p[1]), glm::max(p[2], p[3]));
  };
  double a_lo, a_hi, b_lo, b_hi;
  product(lo[0][0], hi[0][0], lo[1][1], hi[1][1], a_lo, a_hi);  // df1/ds * df2/dt
  product(lo[0][1], hi[0][1], lo[1][0], hi[1][0], b_lo, b_hi);  // df1/dt * df2/ds
  const double det_lo = a_lo - b_hi, det_hi = a_hi - b_lo;
  const double slack = 1e-12 * (glm::max(std::fabs(a_lo), std::fabs(a_hi)) +
                                glm::max(std::fabs(b_lo), std::fabs(b_hi)));
  return det_lo > slack || det_hi < -slack;
}

// Roots of one piece, found by subdividing the projected piece with an explicit stack
// while its box holds the 2D origin (Martin et al. 2000), then by Newton's method from the
// centre of a cell that is flat (the piece's flatness levels) and provably holds at most
// one root (single_root_cell). A cell whose Newton iteration does not converge inside it is
// subdivided further, down to kMaxPatchDepth halvings, so two roots close together are
// separated rather than merged, and a root is not lost to a Newton step that left its cell.
// Newton roots anywhere in the piece are kept (PatchRoots::add merges the duplicates).
// `closest` narrows t_hi to the nearest root found so far.
inline constexpr std::uint32_t kMaxPatchDepth = 16;
// Newton's starts in a cell, as fractions of its extent in (s, t): the centre first (a
// cell proven to hold one root uses it alone), then the corners and the quarter points.
inline constexpr int kCellStarts = 9;
inline constexpr double kCellStartFractions[kCellStarts][2] = {
    {0.5, 0.5},   {0.0, 0.0},   {1.0, 0.0},   {0.0, 1.0},  {1.0, 1.0},
    {0.25, 0.25}, {0.75, 0.25}, {0.25, 0.75}, {0.75, 0.75}};
inline constexpr int kPatchStackSize = static_cast<int>(kMaxPatchDepth) + 2;

// Whether the ray meets the piece's control box within [t_lo, t_hi] (slab test in double,
// widened by a relative 1e-9 so rounding never drops a box the ray grazes).
TESSERA_HD TESSERA_INLINE bool ray_meets_box(const RayPlanes& ray, const dvec3& lower,
                                             const dvec3& upper) {
  double t0 = ray.t_lo, t1 = ray.t_hi;
  for (int axis = 0; axis < 3; ++axis) {
    const double pad = 1e-9 * (upper[axis] - lower[axis]) +
                       1e-15 * (std::fabs(lower[axis]) + std::fabs(upper[axis]));
    const double lo = lower[axis] - pad - ray.origin[axis];
    const double hi = upper[axis] + pad - ray.origin[axis];
    const double d = ray.direction[axis];
    if (d == 0.0) {
      if (lo > 0.0 || hi < 0.0) return false;
      continue;
    }
    double a = lo / d, b = hi / d;
    if (a > b) {
      const double swap = a;
      a = b;
      b = swap;
    }
    t0 = glm::max(t0, a);
    t1 = glm::min(t1, b);
  }
  return t0 <= t1 * (1.0 + 1e-12) + 1e-300;
}

// Which edges of the piece collapse to one point (the poles of a sphere of revolution):
// the control points along the edge coincide (to rounding of the piece's extent).
struct CollapsedEdges {
  bool s0, s1, t0, t1;
};

TESSERA_HD TESSERA_INLINE CollapsedEdges collapsed_edges(const RationalBezierPatch& piece) {
  const dvec3 extent = piece.upper - piece.lower;
  const double tolerance_squared = 1e-24 * glm::dot(extent, extent);
  const auto collapsed = [&](int i0, int j0, int di, int dj) {
    for (int k = 1; k < 4; ++k) {
      const dvec3 step = piece.point[i0 + k * di][j0 + k * dj] - piece.point[i0][j0];
      if (glm::dot(step, step) > tolerance_squared) return false;
    }
    return true;
  };
  return {collapsed(0, 0, 0, 1), collapsed(3, 0, 0, 1), collapsed(0, 0, 1, 0),
          collapsed(0, 3, 1, 0)};
}

TESSERA_HD TESSERA_INLINE void piece_roots(const RationalBezierPatch& piece,
                                           const SplinePatch& patch, RayPlanes& ray, bool closest,
                                           PatchRoots& roots) {
  if (!ray_meets_box(ray, piece.lower, piece.upper)) return;
  ProjectedCell stack[kPatchStackSize];
  int top = 0;
  ProjectedCell& root = stack[top++];
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const dvec3 relative = piece.point[i][j] - ray.origin;
      const double w = piece.weight[i][j];
      root.c[i][j][0] = w * glm::dot(ray.n1, relative);
      root.c[i][j][1] = w * glm::dot(ray.n2, relative);
      root.c[i][j][2] = w * glm::dot(ray.direction, relative) * ray.inverse_dd;
      root.c[i][j][3] = w;
    }
  }
  root.s0 = root.t0 = 0.0;
  root.s1 = root.t1 = 1.0;
  root.level_u = root.level_v = 0;
  // Newton runs on the whole piece's projection (not the cell's), so a root is reported
  // with the piece's parameters wherever the iteration ends.
  double projected[4][4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) projected[i][j][k] = root.c[i][j][k];
  const double direction_length = std::sqrt(1.0 / ray.inverse_dd);
  const double band = ray.origin_error + 1e-13 * (patch.size + max_abs(piece.point[0][0]));
  // The start-surface test below costs a dozen surface evaluations per root; it can only
  // succeed when the origin is within the band of the piece, hence of its control box (the
  // piece lies in the hull of its control points).
  const dvec3 outside = glm::max(piece.lower - ray.origin, ray.origin - piece.upper);
  const bool origin_near_piece = glm::length(glm::max(outside, dvec3(0.0))) <= band;
  CollapsedEdges collapsed{};
  bool collapsed_known = false;  // formed at the first cell that needs it: few rays do
  while (top > 0) {
    const ProjectedCell cell = stack[--top];
    if (!cell_may_hit(cell, ray.t_lo, ray.t_hi)) continue;
    const bool at_depth_limit = cell.level_u + cell.level_v >= kMaxPatchDepth;
    const bool flat = cell.level_u >= piece.levels_u && cell.level_v >= piece.levels_v;
    const bool single = flat && single_root_cell(cell);
    bool subdivide = !at_depth_limit && !single;
    if (!subdivide) {
      // At the depth limit a cell not proven to hold one root may hold two close ones (a
      // ray within ~1e-3 of tangency): Newton from its corners and quarter points too,
      // which reach the roots on either side of the fold (each root's basin can be a
      // fraction of the cell when the ray also runs nearly along an isoparametric line),
      // and from beside the collapsed edges the cell touches (a pole, where the corners'
      // Jacobian is singular and the other starts are drawn to a root farther out).
      const int starts = single ? 1 : kCellStarts + 4;
      if (!single && !collapsed_known) {
        collapsed = collapsed_edges(piece);
        collapsed_known = true;
      }
      bool converged_in_cell = false;
      for (int start = 0; start < starts; ++start) {
        double fraction_s, fraction_t;
        if (start < kCellStarts) {
          fraction_s = kCellStartFractions[start][0];
          fraction_t = kCellStartFractions[start][1];
        } else {
          const int edge = start - kCellStarts;
          const bool touches = (edge == 0 && collapsed.s0 && cell.s0 == 0.0) ||
                               (edge == 1 && collapsed.s1 && cell.s1 == 1.0) ||
                               (edge == 2 && collapsed.t0 && cell.t0 == 0.0) ||
                               (edge == 3 && collapsed.t1 && cell.t1 == 1.0);
          if (!touches) continue;
          fraction_s = edge == 0 ? 1e-3 : edge == 1 ? 1.0 - 1e-3 : 0.5;
          fraction_t = edge == 2 ? 1e-3 : edge == 3 ? 1.0 - 1e-3 : 0.5;
        }
        double s = cell.s0 + fraction_s * (cell.s1 - cell.s0);
        double t = cell.t0 + fraction_t * (cell.t1 - cell.t0);
        double root_t;
        if (!newton_projected(projected, patch.size, direction_length, s, t, root_t)) continue;
        const double margin = 1e-9;
        converged_in_cell = converged_in_cell || (s >= cell.s0 - margin && s <= cell.s1 + margin &&
                                                  t >= cell.t0 - margin && t <= cell.t1 + margin);
        // A ray that starts on the patch finds it again near its origin (see
        // is_start_surface_root): dropped when the origin and the midpoint to the root
        // are both within the origin's uncertainty of the surface.
        const bool start_surface =
            origin_near_piece && local_distance(piece, ray.origin, s, t) <= band &&
            local_distance(piece, ray.origin + (0.5 * root_t) * ray.direction, s, t) <= band;
        if (root_t >= ray.t_lo && root_t <= ray.t_hi && !start_surface) {
          const double u = piece.u0 + s * (piece.u1 - piece.u0);
          const double v = piece.v0 + t * (piece.v1 - piece.v0);
          const double t_tolerance = 1e-10 * (std::fabs(root_t) + patch.size / direction_length);
          if (roots.add(root_t, u, v, t_tolerance, 1e-7 * (patch.u1 - patch.u0),
                        1e-7 * (patch.v1 - patch.v0)) &&
              closest)
            ray.t_hi = root_t;
        }
      }
      if (converged_in_cell) continue;
      subdivide = !at_depth_limit;
    }
    if (subdivide && top + 2 <= kPatchStackSize) {
      const bool split_u = cell.level_u < piece.levels_u;
      const bool split_v = cell.level_v < piece.levels_v;
      const bool along_u = (split_u || split_v)
                               ? split_u && (!split_v || cell.level_u <= cell.level_v)
                               : cell.level_u - piece.levels_u <= cell.level_v - piece.levels_v;
      split_cell(cell, along_u, stack[top + 1], stack[top]);
      top += 2;
    }
  }
}

TESSERA_HD TESSERA_INLINE void patch_roots(const SplinePatch& patch, const PreciseRay& ray,
                                           double t_hi, bool closest, PatchRoots& roots) {
  if (!(glm::dot(ray.direction, ray.direction) > 0.0)) return;
  RayPlanes planes = RayPlanes::make(ray, ray.t_min, t_hi);
  for (std::uint32_t k = 0; k < patch.piece_count; ++k)
    piece_roots(patch.pieces[k], patch, planes, closest, roots);
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const SplinePatch& patch, const PreciseRay& ray,
                                         float t_max, HitRecord& hit, std::uint32_t primitive) {
  PatchRoots roots;
  detail::patch_roots(patch, ray, t_max, true, roots);
  bool found = false;
  float best = t_max;
  for (int i = 0; i < roots.count; ++i) {
    float tf;
    if (accept_root(roots.t[i], ray.t_min, best, tf)) {
      best = tf;
      hit.t = tf;
      hit.u = static_cast<float>(roots.u[i]);
      hit.v = static_cast<float>(roots.v[i]);
      hit.primitive = primitive;
      found = true;
    }
  }
  return found;
}

TESSERA_HD TESSERA_INLINE bool intersect(const SplinePatch& patch, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(patch, make_precise_ray(ray), t_max, hit, primitive);
}

TESSERA_HD TESSERA_INLINE int intersect_all(const SplinePatch& patch, const PreciseRay& ray,
                                            float t_max, HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  PatchRoots roots;
  detail::patch_roots(patch, ray, t_max, false, roots);
  int n = 0;
  for (int i = 0; i < roots.count; ++i) {
    float tf;
    if (accept_root(roots.t[i], ray.t_min, t_max, tf)) {
      HitRecord h;
      h.t = tf;
      h.u = static_cast<float>(roots.u[i]);
      h.v = static_cast<float>(roots.v[i]);
      h.primitive = primitive;
      n = insert_hit_sorted(hits, n, max_hits, h);
    }
  }
  return n;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const SplinePatch& patch, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(patch, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

// The piece holding the patch parameters (u, v) (the first one when (u, v) is on a border).
TESSERA_HD TESSERA_INLINE std::uint32_t piece_at(const SplinePatch& patch, double u, double v) {
  u = glm::clamp(u, patch.u0, patch.u1);
  v = glm::clamp(v, patch.v0, patch.v1);
  for (std::uint32_t k = 0; k < patch.piece_count; ++k) {
    const RationalBezierPatch& p = patch.pieces[k];
    if (u >= p.u0 && u <= p.u1 && v >= p.v0 && v <= p.v1) return k;
  }
  return 0;
}

// Unit normal d/du x d/dv at local (s, t). Where that cross product vanishes (a collapsed
// edge, e.g. the pole of a NURBS sphere, where d/du = 0) the normal is the limit from inside:
// the cross product a little towards the piece's centre, at growing distances.
// "Vanishes" is measured against the piece's size: at a pole the rounding noise of the
// zero derivative (~1e-16 size) would pass any test relative to the derivatives themselves.
TESSERA_HD TESSERA_INLINE dvec3 patch_normal(const RationalBezierPatch& piece, double s, double t,
                                             const dvec3& fallback) {
  dvec3 lower, upper;
  control_box(piece, lower, upper);
  const double extent = glm::length(upper - lower);
  const double steps[4] = {0.0, 1e-6, 1e-4, 1e-2};
  for (double step : steps) {
    const double ss = s + step * (0.5 - s) * 2.0, tt = t + step * (0.5 - t) * 2.0;
    const PatchPoint p = evaluate(piece, ss, tt, piece.point[0][0]);
    const dvec3 n = glm::cross(p.du, p.dv);
    const double length = glm::length(n);
    if (length > 1e-10 * extent * extent && std::isfinite(length)) return n / length;
  }
  return fallback;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const SplinePatch& patch,
                                                        const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  si.material = patch.material;
  const dvec3 toward_ray = -glm::normalize(ray.direction);
  if (patch.piece_count == 0) {
    si.position = vec3(ray.origin + static_cast<double>(hit.t) * ray.direction);
    set_face_normal(si, vec3(ray.direction), vec3(toward_ray));
    si.uv = vec2(hit.u, hit.v);
    return si;
  }
  const RationalBezierPatch& piece = patch.pieces[piece_at(patch, hit.u, hit.v)];
  const double du = piece.u1 - piece.u0, dv = piece.v1 - piece.v0;
  double s = glm::clamp((static_cast<double>(hit.u) - piece.u0) / du, 0.0, 1.0);
  double t = glm::clamp((static_cast<double>(hit.v) - piece.v0) / dv, 0.0, 1.0);
  // The stored uv are floats: polish them on the ray in double (Newton from there), so the
  // point does not carry their rounding; kept only if it is still the same hit.
  {
    const detail::RayPlanes planes = detail::RayPlanes::make(ray, ray.t_min, kInfinity);
    double s2 = s, t2 = t;
    dvec3 point;
    if (detail::newton_root(piece, planes, patch.size, s2, t2, point)) {
      const double root_t = glm::dot(ray.direction, point) * planes.inverse_dd;
      if (std::fabs(root_t - hit.t) <= 1e-4 * std::fabs(root_t) + 1e-6 * patch.size) {
        s = s2;
        t = t2;
      }
    }
  }
  const PatchPoint p = evaluate(piece, s, t, piece.point[0][0]);
  si.position = vec3(piece.point[0][0] + p.position);
  const dvec3 normal = patch_normal(piece, s, t, toward_ray);
  set_face_normal(si, vec3(ray.direction), vec3(normal));
  si.uv = vec2(static_cast<float>(piece.u0 + s * du), static_cast<float>(piece.v0 + t * dv));
  return si;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const SplinePatch& patch, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(patch, make_precise_ray(ray), hit);
}

}  // namespace tessera
