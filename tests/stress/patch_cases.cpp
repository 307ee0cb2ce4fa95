// Stress rows for B-spline/NURBS patches and trimmed faces.
//
// Reference for a patch: every root of the ray with each rational Bézier piece, found in
// long double (64-bit significand) by Newton's method on the two ray-plane distances,
// seeded from (a) every cell of a dense 12 x 12 triangulated parameter grid of the piece
// that the ray crosses (triangles widened by 10% so a crossing near a cell edge seeds both
// cells) and (b) the (u, v) of every root the intersector reported (so a reported root is
// confirmed only if long double Newton converges to a root there). Roots are merged by t.
// The pieces are those of the build (knot insertion is checked against Cox-de Boor in the
// unit tests); the evaluation, the solver and the seeding are independent of the
// intersector's subdivision. A root neither the grid nor the intersector finds is missed by
// both: the grid is 12 x 12 per piece against at most 2^3 x 2^3 flatness cells per piece
// of these shapes, so that takes a fold narrower than 1/12 of a piece.
//
// Reference for an analytic trimmed face: the quad-precision roots of reference_shapes.hpp,
// with uv computed from the exact point by the parameterisation's formula; a root is in the
// face by the same exact winding test, and roots whose uv lie within 1e-6 of a loop edge
// are ambiguous (the intersector decides from float uv), either answer accepted.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "reference_shapes.hpp"
#include "sampling.hpp"
#include "stress_cases.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/math/offset_ray.hpp"

namespace tessera::stress {
namespace {

using ld = long double;

struct LVec {
  ld x = 0, y = 0, z = 0;
  LVec() = default;
  LVec(ld a, ld b, ld c) : x(a), y(b), z(c) {}
  explicit LVec(const dvec3& v) : x(v.x), y(v.y), z(v.z) {}
  explicit LVec(const vec3& v) : x(v.x), y(v.y), z(v.z) {}
  LVec operator+(const LVec& o) const { return {x + o.x, y + o.y, z + o.z}; }
  LVec operator-(const LVec& o) const { return {x - o.x, y - o.y, z - o.z}; }
  LVec operator*(ld s) const { return {x * s, y * s, z * s}; }
  dvec3 to_d() const { return dvec3(double(x), double(y), double(z)); }
};
ld ldot(const LVec& a, const LVec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
LVec lcross(const LVec& a, const LVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
ld llength(const LVec& v) {
  return std::sqrt(ldot(v, v));
}

struct LPoint {
  LVec p, du, dv;
};

LPoint evaluate_ld(const RationalBezierPatch& piece, ld s, ld t, const LVec& origin) {
  const auto basis = [](ld x, ld b[4], ld db[4]) {
    const ld y = 1 - x;
    b[0] = y * y * y;
    b[1] = 3 * x * y * y;
    b[2] = 3 * x * x * y;
    b[3] = x * x * x;
    db[0] = -3 * y * y;
    db[1] = 3 * y * y - 6 * x * y;
    db[2] = 6 * x * y - 3 * x * x;
    db[3] = 3 * x * x;
  };
  ld bs[4], dbs[4], bt[4], dbt[4];
  basis(s, bs, dbs);
  basis(t, bt, dbt);
  LVec h, hs, ht;
  ld w = 0, ws = 0, wt = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const ld weight = piece.weight[i][j];
      const LVec wp = (LVec(piece.point[i][j]) - origin) * weight;
      h = h + wp * (bs[i] * bt[j]);
      hs = hs + wp * (dbs[i] * bt[j]);
      ht = ht + wp * (bs[i] * dbt[j]);
      w += weight * bs[i] * bt[j];
      ws += weight * dbs[i] * bt[j];
      wt += weight * bs[i] * dbt[j];
    }
  LPoint out;
  out.p = h * (1 / w);
  out.du = (hs - out.p * ws) * (1 / w);
  out.dv = (ht - out.p * wt) * (1 / w);
  return out;
}

struct LRay {
  LVec origin, direction, n1, n2;
  explicit LRay(const Ray& ray) : origin(ray.origin), direction(ray.direction) {
    // Any two independent vectors perpendicular to d span the same pair of planes.
    const LVec d = direction;
    const LVec a = std::fabs(double(d.x)) < 0.6 ? LVec(1, 0, 0) : LVec(0, 1, 0);
    n1 = lcross(d, a);
    n1 = n1 * (1 / llength(n1));
    n2 = lcross(d, n1);
    n2 = n2 * (1 / llength(n2));
  }
};

struct RefRoot {
  ld t;
  double u, v;  // patch parameters (or surface uv)
  int piece;
  double s, tt;  // local parameters
  // Within 1e-8 outside the piece: a ray aimed at the patch's own edge, rounded to float,
  // passes either side of it; the intersector accepts roots up to 1e-9 outside (so adjacent
  // patches leave no crack), so such roots are ambiguous.
  bool at_edge;
};

bool newton_ld(const RationalBezierPatch& piece, const LRay& ray, double scale, ld& s, ld& t,
               LVec& point) {
  for (int it = 0; it < 60; ++it) {
    const LPoint p = evaluate_ld(piece, s, t, ray.origin);
    const ld f1 = ldot(ray.n1, p.p), f2 = ldot(ray.n2, p.p);
    const ld a = ldot(ray.n1, p.du), b = ldot(ray.n1, p.dv), c = ldot(ray.n2, p.du),
             d = ldot(ray.n2, p.dv);
    const ld det = a * d - b * c;
    point = p.p;
    const ld tol = 1e-16L * scale + 1e-18L * llength(p.p);
    if (std::fabs(f1) <= tol && std::fabs(f2) <= tol)
      return s >= -1e-8L && s <= 1 + 1e-8L && t >= -1e-8L && t <= 1 + 1e-8L;
    if (det == 0) return false;
    ld ds = (-f1 * d + f2 * b) / det, dt = (-a * f2 + c * f1) / det;
    const ld step = std::max(std::fabs(ds), std::fabs(dt));
    if (step > 0.25L) {
      ds *= 0.25L / step;
      dt *= 0.25L / step;
    }
    s += ds;
    t += dt;
    if (!(s > -0.5L && s < 1.5L && t > -0.5L && t < 1.5L)) return false;
  }
  return false;
}

// A patch under test with its reference data.
struct PatchCase {
  SplinePatchPool pool;
  SplinePatch patch{};
  dvec3 center{0.0};
  double radius = 1.0;  // bounding sphere
  // Per piece, the (2*kGrid+1)^2 grid points relative to the centre, in long double.
  static constexpr int kGrid = 12;
  std::vector<LVec> grid;

  PatchCase() = default;
  PatchCase(const PatchCase&) = delete;
  PatchCase& operator=(const PatchCase&) = delete;

  void finish() {
    bind_pieces(patch, pool.pieces.data());
    dvec3 lower(1e300), upper(-1e300);
    for (const auto& piece : pool.pieces)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          lower = glm::min(lower, piece.point[i][j]);
          upper = glm::max(upper, piece.point[i][j]);
        }
    center = 0.5 * (lower + upper);
    radius = 0.5 * glm::length(upper - lower);
    grid.clear();
    for (const auto& piece : pool.pieces)
      for (int i = 0; i <= kGrid; ++i)
        for (int j = 0; j <= kGrid; ++j)
          grid.push_back(evaluate_ld(piece, ld(i) / kGrid, ld(j) / kGrid, LVec(center)).p);
  }
};

// Patch shapes: size ~1 around `center`, random orientation.
dvec3 rotate(const dvec3& p, const dvec3& axis, double angle) {
  return p * std::cos(angle) + glm::cross(axis, p) * std::sin(angle) +
         axis * glm::dot(axis, p) * (1.0 - std::cos(angle));
}

std::vector<double> clamped4() {
  return {0, 0, 0, 0, 1, 1, 1, 1};
}

void cubic_quarter_circle(const dvec3 p[3], dvec3 out[4], double out_w[4]) {
  const double w1 = std::sqrt(0.5);
  const glm::dvec4 h0(p[0], 1.0), h1(p[1] * w1, w1), h2(p[2], 1.0);
  const glm::dvec4 q[4] = {h0, (h0 + 2.0 * h1) / 3.0, (2.0 * h1 + h2) / 3.0, h2};
  for (int i = 0; i < 4; ++i) {
    out_w[i] = q[i].w;
    out[i] = dvec3(q[i]) / q[i].w;
  }
}

enum class PatchKind { kWavy, kSphereOctant, kCylinderQuarter };

void make_patch(PatchKind kind, const dvec3& center, Rng& rng, PatchCase& out) {
  SplinePatchDescription d;
  if (kind == PatchKind::kWavy) {
    d.count_u = d.count_v = 6;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        d.control_points.push_back(
            dvec3((i - 2.5) * 0.4, (j - 2.5) * 0.4, rng.uniform(-0.35, 0.35)));
    for (int i = 0; i < 10; ++i) {
      d.knots_u.push_back(i);
      d.knots_v.push_back(i);
    }
  } else {
    dvec3 a[4], b[4];
    double wa[4], wb[4];
    const dvec3 profile[3] = {dvec3(1, 0, 0), dvec3(1, 0, 1), dvec3(0, 0, 1)};
    const dvec3 turn[3] = {dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};
    cubic_quarter_circle(profile, a, wa);
    cubic_quarter_circle(turn, b, wb);
    d.count_u = d.count_v = 4;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        if (kind == PatchKind::kSphereOctant) {
          d.control_points.push_back(dvec3(a[i].x * b[j].x, a[i].x * b[j].y, a[i].z));
          d.weights.push_back(wa[i] * wb[j]);
        } else {
          d.control_points.push_back(dvec3(b[i].x, b[i].y, j / 3.0));
          d.weights.push_back(wb[i]);
        }
      }
    d.knots_u = d.knots_v = clamped4();
  }
  const dvec3 axis = rng.unit_vector();
  const double angle = rng.uniform(0.0, kTwoPi);
  for (dvec3& p : d.control_points) p = center + rotate(p, axis, angle);
  const std::string error = build_spline_patch(d, out.pool, out.patch);
  if (!error.empty()) std::fprintf(stderr, "stress: patch build failed: %s\n", error.c_str());
  out.finish();
}

// Every reference root of the ray with the patch (sorted by t, t > 0), plus confirmation
// of the intersector's reported roots.
std::vector<RefRoot> patch_reference(const PatchCase& c, const Ray& ray, const HitRecord* reported,
                                     int reported_count) {
  const LRay lray(ray);
  std::vector<RefRoot> roots;
  const double scale = c.patch.size;
  const ld dd = ldot(lray.direction, lray.direction);
  const auto add_root = [&](int piece_index, ld s, ld t) {
    LVec point;
    const RationalBezierPatch& piece = c.patch.pieces[piece_index];
    if (!newton_ld(piece, lray, scale, s, t, point)) return;
    const ld root_t = ldot(lray.direction, point) / dd;
    if (!(root_t > 0)) return;
    for (const RefRoot& r : roots)
      if (std::fabs(double(r.t - root_t)) <= 1e-9 * (std::fabs(double(root_t)) + scale)) return;
    roots.push_back(RefRoot{root_t, piece.u0 + double(s) * (piece.u1 - piece.u0),
                            piece.v0 + double(t) * (piece.v1 - piece.v0), piece_index, double(s),
                            double(t), s < 0 || s > 1 || t < 0 || t > 1});
  };
  const LVec o = lray.origin - LVec(c.center);
  const int stride = PatchCase::kGrid + 1;
  for (std::uint32_t k = 0; k < c.patch.piece_count; ++k) {
    const LVec* g = c.grid.data() + static_cast<std::size_t>(k) * stride * stride;
    for (int i = 0; i < PatchCase::kGrid; ++i)
      for (int j = 0; j < PatchCase::kGrid; ++j)
        for (int half = 0; half < 2; ++half) {
          // Triangle (i,j) (i+1,j) (i,j+1) or (i+1,j+1) (i,j+1) (i+1,j), widened by 10%.
          const int ai = half ? i + 1 : i, aj = half ? j + 1 : j;
          const int bi = half ? i : i + 1, bj = half ? j + 1 : j;
          const int ci = half ? i + 1 : i, cj = half ? j : j + 1;
          const LVec a = g[ai * stride + aj], b = g[bi * stride + bj], cc = g[ci * stride + cj];
          const LVec e1 = b - a, e2 = cc - a;
          const LVec pv = lcross(lray.direction, e2);
          const ld det = ldot(e1, pv);
          if (det == 0) continue;
          const LVec tv = o - a;
          const ld bu = ldot(tv, pv) / det;
          if (bu < -0.1L || bu > 1.1L) continue;
          const LVec qv = lcross(tv, e1);
          const ld bv = ldot(lray.direction, qv) / det;
          if (bv < -0.1L || bu + bv > 1.1L) continue;
          const ld s = (ai + bu * (bi - ai) + bv * (ci - ai)) / PatchCase::kGrid;
          const ld t = (aj + bu * (bj - aj) + bv * (cj - aj)) / PatchCase::kGrid;
          add_root(static_cast<int>(k), std::clamp<ld>(s, 0, 1), std::clamp<ld>(t, 0, 1));
        }
  }
  for (int i = 0; i < reported_count; ++i) {
    const std::uint32_t k = piece_at(c.patch, reported[i].u, reported[i].v);
    const RationalBezierPatch& piece = c.patch.pieces[k];
    add_root(static_cast<int>(k), (reported[i].u - piece.u0) / (piece.u1 - piece.u0),
             (reported[i].v - piece.v0) / (piece.v1 - piece.v0));
  }
  std::sort(roots.begin(), roots.end(),
            [](const RefRoot& a, const RefRoot& b) { return a.t < b.t; });
  return roots;
}

// Distance (long double) from q to the piece near (s, t): Gauss-Newton foot point.
ld local_distance_ld(const RationalBezierPatch& piece, const LVec& q, ld s, ld t) {
  ld best = 1e300L;
  for (int it = 0; it < 8; ++it) {
    const LPoint p = evaluate_ld(piece, s, t, q);
    best = std::min(best, llength(p.p));
    const ld a = ldot(p.du, p.du), b = ldot(p.du, p.dv), c = ldot(p.dv, p.dv);
    const ld g1 = -ldot(p.du, p.p), g2 = -ldot(p.dv, p.p);
    const ld det = a * c - b * b;
    if (!(det > 0)) break;
    s = std::clamp<ld>(s + (c * g1 - b * g2) / det, 0, 1);
    t = std::clamp<ld>(t + (a * g2 - b * g1) / det, 0, 1);
  }
  return best;
}

struct PatchSample {
  dvec3 point, normal;
  double u, v;
};
PatchSample sample_patch(const PatchCase& c, Rng& rng) {
  const std::uint32_t k =
      static_cast<std::uint32_t>(rng.uniform(0.0, c.patch.piece_count)) % c.patch.piece_count;
  const RationalBezierPatch& piece = c.patch.pieces[k];
  const double s = rng.uniform(0.02, 0.98), t = rng.uniform(0.02, 0.98);
  const PatchPoint p = evaluate(piece, s, t, dvec3(0.0));
  return {p.position, glm::normalize(glm::cross(p.du, p.dv)), piece.u0 + s * (piece.u1 - piece.u0),
          piece.v0 + t * (piece.v1 - piece.v0)};
}

[[gnu::noinline]] Ray float_ray(const dvec3& origin, const dvec3& direction) {
  return Ray{vec3(origin), vec3(direction), 0.0f, kInfinity};
}

bool finite3(const vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

double rel(float t, ld reference) {
  return std::fabs(double(t) - double(reference)) / std::fabs(double(reference));
}

// Rays of the current row with at least one ambiguous root; printed per row when
// TESSERA_STRESS_AMBIGUOUS is set (the table has no column for it).
long ambiguous_rays = 0;
RowResult finish_row(const RowResult& result) {
  if (std::getenv("TESSERA_STRESS_AMBIGUOUS"))
    std::printf("  (%ld of %ld rays had an ambiguous root)\n", ambiguous_rays, result.rays);
  ambiguous_rays = 0;
  return result;
}

// Compares closest hit and all hits with the expected roots; hits matching an ambiguous
// root are ignored (accepted either way).
template <typename Shape>
void compare(const Shape& shape, const Ray& ray, const HitRecord& hit, bool found,
             const HitRecord* all, int n_all, const std::vector<ld>& expected,
             const std::vector<ld>& ambiguous, RowResult& result) {
  const auto is_ambiguous = [&](float t) {
    for (ld a : ambiguous)
      if (rel(t, a) <= 1e-4) return true;
    return false;
  };
  ++result.rays;
  if (!ambiguous.empty()) ++ambiguous_rays;
  const long wrong_before = result.wrong;
  if (!expected.empty()) ++result.reference_hits;
  if (found) {
    const SurfaceInteraction si = surface_at(shape, ray, hit);
    if (!std::isfinite(hit.t) || !finite3(si.position) || !finite3(si.geometric_normal) ||
        !finite3(si.shading_normal) || !std::isfinite(si.uv.x) || !std::isfinite(si.uv.y))
      ++result.nan;
  }
  if (found && is_ambiguous(hit.t) && (expected.empty() || hit.t < double(expected[0]))) {
    // an ambiguous root first: accepted
  } else if (found != !expected.empty()) {
    ++result.wrong;
  } else if (found) {
    const double e = rel(hit.t, expected[0]);
    if (e > 1e-3)
      ++result.wrong;
    else
      result.max_relative_t = std::max(result.max_relative_t, e);
  }
  std::vector<float> kept;
  for (int i = 0; i < n_all; ++i)
    if (!is_ambiguous(all[i].t)) kept.push_back(all[i].t);
  bool mismatch = kept.size() != expected.size();
  for (std::size_t i = 0; i < kept.size() && !mismatch; ++i) {
    if (!std::isfinite(kept[i])) {
      ++result.nan;
      mismatch = true;
    } else if (i > 0 && kept[i] < kept[i - 1]) {
      mismatch = true;
    } else {
      const double e = rel(kept[i], expected[i]);
      if (e > 1e-3)
        mismatch = true;
      else
        result.max_relative_t = std::max(result.max_relative_t, e);
    }
  }
  if (mismatch) ++result.all_hits_mismatch;
  static const int limit = [] {
    const char* v = std::getenv("TESSERA_STRESS_VERBOSE");
    return v ? std::atoi(v) : 0;
  }();
  static int printed = 0;
  if ((mismatch || wrong_before != result.wrong) && printed < limit) {
    ++printed;
    std::printf("  o=(%a,%a,%a) d=(%a,%a,%a) found=%d t=%.9g; all:", ray.origin.x, ray.origin.y,
                ray.origin.z, ray.direction.x, ray.direction.y, ray.direction.z, found ? 1 : 0,
                found ? hit.t : -1.0f);
    for (int i = 0; i < n_all; ++i) std::printf(" %.9g", all[i].t);
    std::printf("; expected:");
    for (ld e : expected) std::printf(" %.9g", double(e));
    std::printf("; ambiguous:");
    for (ld e : ambiguous) std::printf(" %.9g", double(e));
    std::printf("\n");
  }
}

enum class PatchFamily {
  kRandom,
  kFarMid,
  kFarExtreme,
  kGrazing,
  kTangent,
  kCollapsedEdge,
  kOnSurface,
};

const char* patch_family_name(PatchFamily f) {
  switch (f) {
    case PatchFamily::kRandom:
      return "random near";
    case PatchFamily::kFarMid:
      return "far 1e2-1e4";
    case PatchFamily::kFarExtreme:
      return "far 1e5-1e6";
    case PatchFamily::kGrazing:
      return "grazing";
    case PatchFamily::kTangent:
      return "tangent";
    case PatchFamily::kCollapsedEdge:
      return "at the pole (collapsed)";
    case PatchFamily::kOnSurface:
      return "origin on surface";
  }
  return "?";
}

Ray generate_patch_ray(const PatchCase& c, PatchFamily family, Rng& rng, bool& on_surface) {
  on_surface = false;
  const auto target = [&]() {
    return rng.coin(0.7) ? sample_patch(c, rng).point : c.center + rng.in_ball(c.radius);
  };
  switch (family) {
    case PatchFamily::kRandom: {
      const dvec3 o = c.center + rng.unit_vector() * (c.radius * rng.uniform(1.05, 5.0));
      return float_ray(o, glm::normalize(target() - o) * rng.log_uniform(0.1, 10.0));
    }
    case PatchFamily::kFarMid:
    case PatchFamily::kFarExtreme: {
      const double distance =
          family == PatchFamily::kFarMid ? rng.log_uniform(1e2, 1e4) : rng.log_uniform(1e5, 1e6);
      const dvec3 o = c.center + rng.unit_vector() * distance;
      return float_ray(o, glm::normalize(target() - o));
    }
    case PatchFamily::kGrazing:
    case PatchFamily::kTangent: {
      const PatchSample s = sample_patch(c, rng);
      const dvec3 t = rng.perpendicular_unit(s.normal);
      dvec3 d = t;
      if (family == PatchFamily::kGrazing) {
        const double angle = rng.log_uniform(1e-5, 1e-1) * (rng.coin() ? 1.0 : -1.0);
        d = glm::normalize(t * std::cos(angle) + s.normal * std::sin(angle));
      }
      return float_ray(s.point - d * rng.uniform(1.0, 3.0), d);
    }
    case PatchFamily::kCollapsedEdge: {
      // The sphere octant's pole: u = 1 (the last profile row). Rays aimed exactly at it
      // or within 1e-6 of it, from any direction.
      const RationalBezierPatch& piece = c.patch.pieces[0];
      dvec3 pole = piece.point[3][0];
      if (rng.coin()) pole += rng.unit_vector() * 1e-6;
      const dvec3 o = pole + rng.unit_vector() * rng.uniform(0.5, 3.0);
      return float_ray(o, glm::normalize(pole - o));
    }
    case PatchFamily::kOnSurface: {
      on_surface = true;
      return float_ray(sample_patch(c, rng).point, rng.unit_vector());
    }
  }
  return float_ray(dvec3(0.0), dvec3(0, 0, 1));
}

std::function<RowResult(int, std::uint64_t)> patch_row(PatchKind kind, PatchFamily family,
                                                       double offset) {
  return [kind, family, offset](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    PatchCase c;
    for (int i = 0; i < rays; ++i) {
      if (i % 16 == 0) {
        c.pool.pieces.clear();
        make_patch(kind,
                   offset > 0.0 ? rng.unit_vector() * rng.log_uniform(1e2, offset) : dvec3(0.0),
                   rng, c);
      }
      bool on_surface = false;
      const Ray ray = generate_patch_ray(c, family, rng, on_surface);
      HitRecord hit;
      const bool found = intersect(c.patch, ray, kInfinity, hit, 3u);
      HitRecord all[16];
      const int n = intersect_all(c.patch, ray, kInfinity, all, 16, 3u);
      const std::vector<RefRoot> roots = patch_reference(c, ray, all, n);
      std::vector<ld> expected, ambiguous;
      const ld band = std::ldexp(1.0L, -23) * max_abs(dvec3(ray.origin)) + 1e-12L;
      for (const RefRoot& r : roots) {
        if (r.at_edge) {
          ambiguous.push_back(r.t);
          continue;
        }
        if (on_surface) {
          // As in evaluate_ray: the midpoint's distance to the surface in units of the band
          // decides start surface (<= 0.5), ambiguous (<= 4) or a real hit.
          const LRay lray(ray);
          const LVec mid = lray.origin + lray.direction * (r.t / 2);
          const ld ratio = local_distance_ld(c.patch.pieces[r.piece], mid, r.s, r.tt) / band;
          if (ratio <= 0.5L) continue;
          if (ratio <= 4.0L) {
            ambiguous.push_back(r.t);
            continue;
          }
        }
        expected.push_back(r.t);
      }
      compare(c.patch, ray, hit, found, all, n, expected, ambiguous, result);
    }
    return finish_row(result);
  };
}

// Spawned rays from hits at offsets up to `offset`: re-hits of the patch within 1e-3 of
// the spawn point that the reference does not have there.
std::function<RowResult(int, std::uint64_t)> patch_spawn_row(PatchKind kind, double offset) {
  return [kind, offset](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    PatchCase c;
    for (int i = 0; i < rays; ++i) {
      if (i % 16 == 0) {
        c.pool.pieces.clear();
        make_patch(kind, rng.unit_vector() * offset, rng, c);
      }
      bool on_surface;
      const Ray ray = generate_patch_ray(c, PatchFamily::kRandom, rng, on_surface);
      HitRecord hit;
      if (!intersect(c.patch, ray, kInfinity, hit, 3u)) continue;
      const SurfaceInteraction si = surface_at(c.patch, ray, hit);
      if (!finite3(si.position) || !finite3(si.geometric_normal)) {
        ++result.nan;
        continue;
      }
      for (int side = 0; side < 2; ++side) {
        const dvec3 n = dvec3(side == 0 ? si.geometric_normal : -si.geometric_normal);
        dvec3 direction = n + rng.unit_vector();
        if (glm::length(direction) < 1e-6) direction = n;
        const Ray spawned =
            float_ray(dvec3(offset_ray_origin(si.position, vec3(n))), glm::normalize(direction));
        ++result.rays;
        HitRecord again;
        if (!intersect(c.patch, spawned, kInfinity, again, 3u)) continue;
        if (!std::isfinite(again.t)) {
          ++result.nan;
          continue;
        }
        const std::vector<RefRoot> reference = patch_reference(c, spawned, &again, 1);
        if (!reference.empty()) ++result.reference_hits;
        if (again.t < 1e-3) {
          const bool real = !reference.empty() && rel(again.t, reference[0].t) < 1e-2;
          if (!real) ++result.wrong;
        } else if (!reference.empty() && rel(again.t, reference[0].t) < 1e-3) {
          result.max_relative_t = std::max(result.max_relative_t, rel(again.t, reference[0].t));
        }
      }
    }
    return result;
  };
}

// ---- trimmed faces

double segment_distance(const dvec2& p, const dvec2& a, const dvec2& b) {
  const dvec2 ab = b - a;
  const double l2 = glm::dot(ab, ab);
  const double h = l2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + h * ab));
}

// Distance in uv from p to the nearest loop edge (over the periodic copies).
double boundary_distance(const TrimRegion& region, const dvec2& p) {
  double best = 1e300;
  const int su = region.periodic.u ? 1 : 0, sv = region.periodic.v ? 1 : 0;
  for (std::uint32_t k = 0; k < region.loop_count; ++k) {
    const TrimLoop& loop = region.loops[region.first_loop + k];
    const dvec2* v = region.points + loop.first_point;
    for (std::uint32_t i = 0; i < loop.point_count; ++i)
      for (int du = -su; du <= su; ++du)
        for (int dv = -sv; dv <= sv; ++dv)
          best = std::min(best,
                          segment_distance(p + dvec2(du, dv), v[i], v[(i + 1) % loop.point_count]));
  }
  return best;
}

// Independent point-in-face for the reference: even-odd crossing parity in long double
// (the test loops are simple polygons, for which it equals the non-zero rule), used only
// for points at least 1e-6 from every edge, where long double decides exactly.
bool crossing_parity(const TrimRegion& region, const TrimLoop& loop, const dvec2& p) {
  bool inside = false;
  const dvec2* v = region.points + loop.first_point;
  for (std::uint32_t i = 0, j = loop.point_count - 1; i < loop.point_count; j = i++) {
    const ld yi = v[i].y, yj = v[j].y, xi = v[i].x, xj = v[j].x;
    if ((yi > p.y) != (yj > p.y) && ld(p.x) < (xj - xi) * (ld(p.y) - yi) / (yj - yi) + xi)
      inside = !inside;
  }
  return inside;
}
bool reference_in_face(const TrimRegion& region, const dvec2& uv) {
  const int su = region.periodic.u ? 1 : 0, sv = region.periodic.v ? 1 : 0;
  const TrimLoop* loops = region.loops + region.first_loop;
  bool in_outer = false;
  for (int du = -su; du <= su; ++du)
    for (int dv = -sv; dv <= sv; ++dv)
      in_outer = in_outer || crossing_parity(region, loops[0], uv + dvec2(du, dv));
  if (!in_outer) return false;
  for (std::uint32_t k = 1; k < region.loop_count; ++k)
    for (int du = -su; du <= su; ++du)
      for (int dv = -sv; dv <= sv; ++dv)
        if (crossing_parity(region, loops[k], uv + dvec2(du, dv))) return false;
  return true;
}

enum class TrimFamily { kRandom, kLoopVertices, kLoopEdges, kNearEdges };

const char* trim_family_name(TrimFamily f) {
  switch (f) {
    case TrimFamily::kRandom:
      return "random near";
    case TrimFamily::kLoopVertices:
      return "at loop vertices";
    case TrimFamily::kLoopEdges:
      return "along loop edges";
    case TrimFamily::kNearEdges:
      return "1e-5..1e-3 off edges";
  }
  return "?";
}

// A uv point of the face's loops: a vertex, or a point on an edge.
dvec2 loop_point(const TrimRegion& region, TrimFamily family, Rng& rng) {
  const std::uint32_t k =
      static_cast<std::uint32_t>(rng.uniform(0.0, region.loop_count)) % region.loop_count;
  const TrimLoop& loop = region.loops[region.first_loop + k];
  const std::uint32_t i =
      static_cast<std::uint32_t>(rng.uniform(0.0, loop.point_count)) % loop.point_count;
  const dvec2 a = region.points[loop.first_point + i];
  const dvec2 b = region.points[loop.first_point + (i + 1) % loop.point_count];
  if (family == TrimFamily::kLoopVertices) return a;
  const dvec2 on_edge = a + rng.uniform() * (b - a);
  if (family == TrimFamily::kLoopEdges) return on_edge;
  // Off the edge by 1e-5 to 1e-3 (uv units) to either side: decided exactly by the winding
  // test, far above the float rounding of uv.
  const dvec2 along = glm::normalize(b - a);
  return on_edge + dvec2(-along.y, along.x) * (rng.log_uniform(1e-5, 1e-3) * (rng.coin() ? 1 : -1));
}

// The trimmed wavy patch: outer loop a concave polygon of the domain [3, 6]^2, one hole.
std::vector<std::vector<dvec2>> wavy_loops() {
  return {{{3.0, 3.0}, {6.0, 3.0}, {6.0, 6.0}, {4.7, 6.0}, {4.5, 4.4}, {4.2, 6.0}, {3.0, 6.0}},
          {{3.5, 3.5}, {4.1, 3.6}, {3.8, 4.2}}};
}

std::function<RowResult(int, std::uint64_t)> trimmed_patch_row(TrimFamily family) {
  return [family](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    PatchCase c;
    TrimPool trims;
    Trimmed<SplinePatch> face{};
    for (int i = 0; i < rays; ++i) {
      if (i % 16 == 0) {
        c.pool.pieces.clear();
        trims = TrimPool{};
        make_patch(PatchKind::kWavy, dvec3(0.0), rng, c);
        build_trimmed_face(c.patch, wavy_loops(), trims, face);
      }
      dvec3 target;
      if (family == TrimFamily::kRandom) {
        target = sample_patch(c, rng).point;
      } else {
        const dvec2 uv = loop_point(face.region, family, rng);
        const std::uint32_t k = piece_at(c.patch, uv.x, uv.y);
        const RationalBezierPatch& piece = c.patch.pieces[k];
        target = evaluate(piece, (uv.x - piece.u0) / (piece.u1 - piece.u0),
                          (uv.y - piece.v0) / (piece.v1 - piece.v0), dvec3(0.0))
                     .position;
      }
      const dvec3 o = c.center + rng.unit_vector() * (c.radius * rng.uniform(1.05, 5.0));
      const Ray ray = float_ray(o, glm::normalize(target - o));
      HitRecord hit;
      const bool found = intersect(face, ray, kInfinity, hit, 3u);
      HitRecord all[16], surface_all[16];
      const int n = intersect_all(face, ray, kInfinity, all, 16, 3u);
      const int n_surface = intersect_all(c.patch, ray, kInfinity, surface_all, 16, 3u);
      const std::vector<RefRoot> roots = patch_reference(c, ray, surface_all, n_surface);
      std::vector<ld> expected, ambiguous;
      const double extent = c.patch.u1 - c.patch.u0;
      for (const RefRoot& r : roots) {
        const dvec2 uv(r.u, r.v);
        if (r.at_edge || boundary_distance(face.region, uv) <= 1e-6 * extent)
          ambiguous.push_back(r.t);
        else if (reference_in_face(face.region, uv))
          expected.push_back(r.t);
      }
      compare(face, ray, hit, found, all, n, expected, ambiguous, result);
    }
    return finish_row(result);
  };
}

// uv of a point of the (unit-radius-normalised) sphere and cylinder, by the formulas of
// sphere.hpp and cylinder.hpp, from the exact point.
dvec2 sphere_uv(const Sphere& s, const dvec3& p) {
  const dvec3 n = glm::normalize(p - dvec3(s.center));
  const double theta = std::acos(std::clamp(-n.y, -1.0, 1.0));
  const double phi = std::atan2(-n.z, n.x) + 3.14159265358979323846;
  return dvec2(phi / kTwoPi, theta / 3.14159265358979323846);
}
dvec2 cylinder_uv(const Cylinder& c, const dvec3& p) {
  const AxisFrame frame = AxisFrame::from_axis(c.axis);
  const dvec3 l = frame.to_local(p - dvec3(c.base));
  double phi = std::atan2(l.y, l.x);
  if (phi < 0.0) phi += kTwoPi;
  return dvec2(phi / kTwoPi, l.z / c.height);
}

template <typename Surface>
std::function<RowResult(int, std::uint64_t)> trimmed_analytic_row(TrimFamily family) {
  return [family](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    for (int i = 0; i < rays; ++i) {
      TrimPool trims;
      Trimmed<Surface> face{};
      Surface surface;
      std::vector<std::vector<dvec2>> loops;
      const dvec3 axis = rng.unit_vector();
      if constexpr (std::is_same_v<Surface, Sphere>) {
        surface = Sphere{vec3(0.0f), 1.0f, 0};
        // A band v in [0.2, 0.8] all the way round with a hole across the seam.
        loops = {{{0, 0.2}, {0.5, 0.2}, {1, 0.2}, {1, 0.8}, {0.5, 0.8}, {0, 0.8}},
                 {{0.93, 0.35}, {0.07, 0.4}, {0.05, 0.65}, {0.9, 0.6}}};
      } else {
        surface = Cylinder::make(vec3(-0.5 * axis), vec3(axis), 0.5f, 1.0f, false, 0);
        // A window across the seam with a notch.
        loops = {{{0.8, 0.1}, {0.2, 0.1}, {0.2, 0.9}, {0.05, 0.5}, {0.8, 0.9}}};
      }
      build_trimmed_face(surface, loops, trims, face);
      dvec3 target;
      const auto point_at = [&](const dvec2& uv) {
        if constexpr (std::is_same_v<Surface, Sphere>) {
          const double theta = uv.y * 3.14159265358979323846;
          const double phi = uv.x * kTwoPi - 3.14159265358979323846;
          return dvec3(std::sin(theta) * std::cos(phi), -std::cos(theta),
                       -std::sin(theta) * std::sin(phi));
        } else {
          const AxisFrame frame = AxisFrame::from_axis(surface.axis);
          const double phi = uv.x * kTwoPi;
          return dvec3(surface.base) +
                 frame.to_world(dvec3(0.5 * std::cos(phi), 0.5 * std::sin(phi), uv.y));
        }
      };
      if (family == TrimFamily::kRandom)
        target = point_at(dvec2(rng.uniform(), rng.uniform()));
      else
        target = point_at(loop_point(face.region, family, rng));
      const dvec3 o = rng.unit_vector() * rng.uniform(1.2, 5.0);
      const Ray ray = float_ray(o, glm::normalize(target - o));
      HitRecord hit;
      const bool found = intersect(face, ray, kInfinity, hit, 3u);
      HitRecord all[16];
      const int n = intersect_all(face, ray, kInfinity, all, 16, 3u);
      const ReferenceHits reference = reference_hits(surface, to_qray(ray));
      std::vector<ld> expected, ambiguous;
      for (int k = 0; k < reference.count; ++k) {
        const double t = to_double(reference.t[k]);
        const QVec qp = to_qray(ray).origin + reference.t[k] * to_qray(ray).direction;
        const dvec3 p = qp.to_dvec3();
        dvec2 uv;
        if constexpr (std::is_same_v<Surface, Sphere>)
          uv = sphere_uv(surface, p);
        else
          uv = cylinder_uv(surface, p);
        if (boundary_distance(face.region, uv) <= 1e-6)
          ambiguous.push_back(t);
        else if (reference_in_face(face.region, uv))
          expected.push_back(t);
      }
      compare(face, ray, hit, found, all, n, expected, ambiguous, result);
    }
    return finish_row(result);
  };
}

}  // namespace

void add_patch_rows(std::vector<Row>& rows,
                    const std::function<Bounds(const std::string&, const std::string&)>& bounds) {
  const auto add = [&](const std::string& surface, const std::string& family,
                       std::function<RowResult(int, std::uint64_t)> run, int rays) {
    rows.push_back(Row{surface, family, rays, bounds(surface, family), std::move(run)});
  };
  const struct {
    const char* name;
    PatchKind kind;
  } kinds[] = {{"bspline patch (wavy)", PatchKind::kWavy},
               {"nurbs sphere octant", PatchKind::kSphereOctant},
               {"nurbs cylinder 1/4", PatchKind::kCylinderQuarter}};
  for (const auto& k : kinds) {
    for (PatchFamily f : {PatchFamily::kRandom, PatchFamily::kFarMid, PatchFamily::kFarExtreme,
                          PatchFamily::kGrazing, PatchFamily::kTangent, PatchFamily::kOnSurface})
      add(k.name, patch_family_name(f), patch_row(k.kind, f, 0.0), 500);
    add(k.name, "offset 1e2-1e5", patch_row(k.kind, PatchFamily::kRandom, 1e5), 500);
    if (k.kind == PatchKind::kSphereOctant)
      add(k.name, patch_family_name(PatchFamily::kCollapsedEdge),
          patch_row(k.kind, PatchFamily::kCollapsedEdge, 0.0), 500);
    for (double offset : {1e1, 1e3, 1e5}) {
      char name[64];
      std::snprintf(name, sizeof name, "spawn @%.0e", offset);
      add(k.name, name, patch_spawn_row(k.kind, offset), 300);
    }
  }
  for (TrimFamily f : {TrimFamily::kRandom, TrimFamily::kLoopVertices, TrimFamily::kLoopEdges,
                       TrimFamily::kNearEdges}) {
    add("trimmed patch (hole)", trim_family_name(f), trimmed_patch_row(f), 500);
    add("trimmed sphere (seam)", trim_family_name(f), trimmed_analytic_row<Sphere>(f), 1000);
    add("trimmed cylinder(seam)", trim_family_name(f), trimmed_analytic_row<Cylinder>(f), 1000);
  }
}

}  // namespace tessera::stress
