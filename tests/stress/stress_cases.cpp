#include "stress_cases.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "reference_shapes.hpp"
#include "sampling.hpp"
#include "tessera/geometry/triangle_precise.hpp"
#include "tessera/math/offset_ray.hpp"
#include "tessera/math/solver_bracketed.hpp"
#include "tessera/math/solver_quartic.hpp"

namespace tessera::stress {
namespace {

enum class Family {
  kRandom,       // origins near, directions aimed into the bounding sphere, any length
  kFarMid,       // origins 1e2 to 1e4 sizes away
  kFarExtreme,   // origins 1e5 to 1e6 sizes away
  kGrazing,      // through a surface point at 1e-5 to 1e-1 rad from the tangent plane
  kTangent,      // along a tangent line (then rounded to float)
  kNearTangent,  // a tangent line moved 1e-6 sizes off the surface, either side
  kAxisAligned,  // directions along +-x, +-y, +-z
  kAlongAxis,    // along the shape's axis (normal for flat shapes), on and off the axis
  kOnSurface,    // origin on the surface (rounded to float), any direction
  kParallel,     // flat shapes: parallel to the plane, 1e-6 to 1e-3 sizes off it
};

const char* family_name(Family f) {
  switch (f) {
    case Family::kRandom:
      return "random near";
    case Family::kFarMid:
      return "far 1e2-1e4";
    case Family::kFarExtreme:
      return "far 1e5-1e6";
    case Family::kGrazing:
      return "grazing";
    case Family::kTangent:
      return "tangent";
    case Family::kNearTangent:
      return "tangent +-1e-6";
    case Family::kAxisAligned:
      return "axis-aligned";
    case Family::kAlongAxis:
      return "along axis";
    case Family::kOnSurface:
      return "origin on surface";
    case Family::kParallel:
      return "parallel +-1e-6..1e-3";
  }
  return "?";
}

// Not inlined on purpose: GCC 12's SLP vectorizer (-O2/-O3) was seen to forward the double
// values into the inlined intersector instead of their float roundings (the reference,
// reading the stored floats, then disagreed). Returning the ray from an opaque call makes
// the rounding to float happen before any use.
[[gnu::noinline]] Ray make_ray(const dvec3& origin, const dvec3& direction) {
  return Ray{vec3(origin), vec3(direction), 0.0f, kInfinity};
}

struct GeneratedRay {
  Ray ray;
  bool starts_on_surface = false;
};

template <typename Shape>
dvec3 tangent_direction(const Shape&, const SurfacePoint& s, Rng& rng) {
  return rng.perpendicular_unit(s.normal);
}
// On a cylinder or cone side a tangent line along the generator lies in the surface (the
// equation vanishes identically); keep tangents at least ~45 degrees off the generator.
dvec3 lateral_tangent(const dvec3& axis, const SurfacePoint& s, Rng& rng) {
  const dvec3 around = glm::cross(axis, s.normal);
  const double l = glm::length(around);
  if (l < 1e-6) return rng.perpendicular_unit(s.normal);
  const dvec3 e_phi = around / l;
  const dvec3 along = glm::normalize(glm::cross(s.normal, e_phi));
  const double a = rng.uniform(-0.7, 0.7);
  return glm::normalize(e_phi * std::sqrt(1.0 - a * a) + along * a);
}
dvec3 tangent_direction(const Cylinder& c, const SurfacePoint& s, Rng& rng) {
  return lateral_tangent(glm::normalize(dvec3(c.axis)), s, rng);
}
dvec3 tangent_direction(const Cone& c, const SurfacePoint& s, Rng& rng) {
  return lateral_tangent(glm::normalize(dvec3(c.axis)), s, rng);
}

template <typename Shape>
dvec3 random_target(const Shape& shape, Rng& rng) {
  if (rng.coin(0.5)) return sample_surface(shape, rng).point;
  const BoundingSphere b = bounding_sphere(shape);
  return b.center + rng.in_ball(b.radius);
}

template <typename Shape>
GeneratedRay generate_once(const Shape& shape, Family family, double scale, Rng& rng) {
  const BoundingSphere b = bounding_sphere(shape);
  switch (family) {
    case Family::kRandom: {
      const dvec3 origin = rng.coin(0.2)
                               ? b.center + rng.in_ball(b.radius)
                               : b.center + rng.unit_vector() * (b.radius * rng.uniform(1.05, 5.0));
      const dvec3 target = random_target(shape, rng);
      const dvec3 d = target - origin;
      if (glm::length(d) == 0.0) return {make_ray(origin, rng.unit_vector())};
      return {make_ray(origin, glm::normalize(d) * rng.log_uniform(0.1, 10.0))};
    }
    case Family::kFarMid:
    case Family::kFarExtreme: {
      const double distance = family == Family::kFarMid ? rng.log_uniform(1e2, 1e4) * scale
                                                        : rng.log_uniform(1e5, 1e6) * scale;
      const dvec3 origin = b.center + rng.unit_vector() * distance;
      return {make_ray(origin, glm::normalize(random_target(shape, rng) - origin))};
    }
    case Family::kGrazing:
    case Family::kTangent:
    case Family::kNearTangent: {
      SurfacePoint s = sample_surface(shape, rng);
      while (on_flat_part(shape, s)) s = sample_surface(shape, rng);
      const dvec3 t = tangent_direction(shape, s, rng);
      dvec3 through = s.point;
      dvec3 direction = t;
      if (family == Family::kGrazing) {
        const double angle = rng.log_uniform(1e-5, 1e-1) * (rng.coin() ? 1.0 : -1.0);
        direction = glm::normalize(t * std::cos(angle) + s.normal * std::sin(angle));
      } else if (family == Family::kNearTangent) {
        through += s.normal * (1e-6 * scale * (rng.coin() ? 1.0 : -1.0));
      }
      const double back = rng.uniform(1.0, 4.0) * scale;
      return {make_ray(through - direction * back, direction)};
    }
    case Family::kAxisAligned: {
      const int axis = static_cast<int>(rng.uniform(0.0, 3.0)) % 3;
      dvec3 e(0.0);
      e[axis] = rng.coin() ? 1.0 : -1.0;
      const dvec3 target = random_target(shape, rng);
      return {make_ray(target - e * (b.radius * rng.uniform(1.5, 4.0)), e)};
    }
    case Family::kAlongAxis: {
      const dvec3 axis = shape_axis(shape, rng) * (rng.coin() ? 1.0 : -1.0);
      const double offset = rng.coin(0.3) ? 0.0 : rng.uniform(0.0, b.radius);
      const dvec3 start = b.center + rng.perpendicular_unit(axis) * offset -
                          axis * (b.radius * rng.uniform(1.5, 4.0));
      return {make_ray(start, axis)};
    }
    case Family::kOnSurface: {
      const SurfacePoint s = sample_surface(shape, rng);
      return {make_ray(s.point, rng.unit_vector()), true};
    }
    case Family::kParallel: {
      const SurfacePoint s = sample_surface(shape, rng);
      const dvec3 t = rng.perpendicular_unit(s.normal);
      const double offset = rng.log_uniform(1e-6, 1e-3) * scale * (rng.coin() ? 1.0 : -1.0);
      return {make_ray(s.point + s.normal * offset - t * (b.radius * rng.uniform(1.5, 4.0)), t)};
    }
  }
  return {make_ray(dvec3(0.0), dvec3(0.0, 0.0, 1.0))};
}

// Origins of every family but "origin on surface" are kept more than ~4 ulps of their own
// coordinates off the surface: closer than that the intersectors treat the ray as starting
// on the surface (see is_start_surface_root), which is that family's subject.
template <typename Shape>
GeneratedRay generate(const Shape& shape, Family family, double scale, Rng& rng) {
  for (;;) {
    const GeneratedRay g = generate_once(shape, family, scale, rng);
    if (family == Family::kOnSurface || !origin_on_surface(shape, dvec3(g.ray.origin))) return g;
  }
}

bool finite(const vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

double relative_error(float t, quad reference) {
  return std::fabs(static_cast<double>(t) - to_double(reference)) / std::fabs(to_double(reference));
}

// TESSERA_STRESS_VERBOSE=N prints the first N wrong cases of each kind (for diagnosis):
// whether the case counted by `printed` is still among them.
bool verbose_slot(int& printed) {
  static const int limit = [] {
    const char* v = std::getenv("TESSERA_STRESS_VERBOSE");
    return v ? std::atoi(v) : 0;
  }();
  if (printed >= limit) return false;
  ++printed;
  return true;
}

// Prints a wrong ray (TESSERA_STRESS_VERBOSE).
void report_wrong_ray(const Ray& ray, float found_t, const quad* expected, int expected_count,
                      int ambiguous) {
  static int printed = 0;
  if (!verbose_slot(printed)) return;
  std::printf("  wrong: o=(%a,%a,%a) d=(%a,%a,%a) found t=%.9g; reference (%d ambiguous):",
              ray.origin.x, ray.origin.y, ray.origin.z, ray.direction.x, ray.direction.y,
              ray.direction.z, found_t, ambiguous);
  for (int i = 0; i < expected_count; ++i) std::printf(" %.12g", to_double(expected[i]));
  std::printf("\n");
}

// The factor a hit's relative t error is scaled by before it is judged, for a root at
// reference_t. For flat shapes it is |cos| of the angle between the ray and the normal, so
// the error judged is the hit's distance from the plane relative to the distance travelled
// (the backward error): a ray within c of parallel has t conditioned as 1/c, and no
// computation in the precision of its inputs pins t down better than that (a double-path
// plane meets a ray 2e-12 off parallel with t off by 3e-5, yet 6e-17 off the plane).
// Curved shapes are judged on t itself: 1.
template <typename Shape>
double t_conditioning(const Shape&, const Ray&, double /*reference_t*/) {
  return 1.0;
}
double flat_conditioning(const dvec3& normal, const Ray& ray) {
  return std::fabs(glm::dot(glm::normalize(normal), glm::normalize(dvec3(ray.direction))));
}
double t_conditioning(const Plane& p, const Ray& ray, double) {
  return flat_conditioning(dvec3(p.normal), ray);
}
double t_conditioning(const Disk& d, const Ray& ray, double) {
  return flat_conditioning(dvec3(d.normal), ray);
}
double t_conditioning(const Quad& q, const Ray& ray, double) {
  return flat_conditioning(glm::cross(dvec3(q.u), dvec3(q.v)), ray);
}
dvec3 triangle_normal(const Triangle& t) {
  return glm::cross(dvec3(t.p1) - dvec3(t.p0), dvec3(t.p2) - dvec3(t.p0));
}
// The float triangle (Woop's test) computes in float coordinates relative to the ray's
// origin, so its hit lies within a few 2^-24 of the vertices' distance from the origin, not
// of the distance travelled: a hit close to an origin near a large triangle, or near a
// small one far out in coordinates, is that much less precise relative to t. Its backward
// error is judged against the larger of the two.
double t_conditioning(const Triangle& t, const Ray& ray, double reference_t) {
  const dvec3 o(ray.origin);
  const double reach = std::max(
      {glm::length(dvec3(t.p0) - o), glm::length(dvec3(t.p1) - o), glm::length(dvec3(t.p2) - o)});
  const double travelled = reference_t * glm::length(dvec3(ray.direction));
  return flat_conditioning(triangle_normal(t), ray) * travelled / std::max(travelled, reach);
}

// For a ray that starts on the surface, the factor a root's relative t error is scaled by:
// a root a distance d = t |direction| from the origin forms a close pair with the origin's
// own root, which the intersectors drop, and the rounding of the polynomial's terms
// (~2^-52 of them at the shape's size R) moves it by ~2^-52 R^2 / d, a relative
// 2^-52 (R / d)^2. The error is judged against 1e-7 plus four times that: unchanged for
// roots across the shape, and 1e-6 for a thin tube's exit 2e-5 R away (measured 3.3e-7)
// or a spindle torus's other sheet 8.7e-6 R away (1.4e-6).
double start_pair_conditioning(double radius, const Ray& ray, double reference_t) {
  const double d = reference_t * glm::length(dvec3(ray.direction));
  const double pair = 4.0 * 0x1p-52 * (radius / d) * (radius / d);
  return 1e-7 / (1e-7 + pair);
}

// The error a hit at `found_t` is judged by against the reference root: relative to it,
// scaled by both factors above.
template <typename Shape>
double judged_error(const Shape& shape, const GeneratedRay& generated, float found_t,
                    quad reference) {
  const double reference_t = to_double(reference);
  double e = relative_error(found_t, reference) * t_conditioning(shape, generated.ray, reference_t);
  if (generated.starts_on_surface)
    e *= start_pair_conditioning(bounding_sphere(shape).radius, generated.ray, reference_t);
  return e;
}

// Compares intersect, intersect_all and surface_at on one ray with the reference.
template <typename Shape>
void evaluate_ray(const Shape& shape, const GeneratedRay& generated, RowResult& result) {
  const Ray& ray = generated.ray;
  const ReferenceHits reference = reference_hits(shape, to_qray(ray));
  // For rays that start on the surface each reference root is classified by how far the
  // ray's midpoint between origin and root is from the surface, in units of the band the
  // intersectors use: <= 0.5 it is the start surface (must not be reported), > 4 a real hit
  // (must be), in between it is ambiguous (either answer is accepted).
  quad expected[8];
  int expected_count = 0;
  quad ambiguous[8];
  int ambiguous_count = 0;
  for (int i = 0; i < reference.count; ++i) {
    if (generated.starts_on_surface) {
      const dvec3 o(ray.origin);
      const dvec3 midpoint = o + (0.5 * to_double(reference.t[i])) * dvec3(ray.direction);
      const double ratio = band_ratio(shape, o, midpoint);
      if (ratio <= 0.5) continue;
      if (ratio <= 4.0) {
        ambiguous[ambiguous_count++] = reference.t[i];
        continue;
      }
    }
    expected[expected_count++] = reference.t[i];
  }
  const auto is_ambiguous = [&](float t) {
    for (int i = 0; i < ambiguous_count; ++i)
      if (relative_error(t, ambiguous[i]) <= 1e-3) return true;
    return false;
  };
  ++result.rays;
  if (expected_count > 0) ++result.reference_hits;

  HitRecord hit;
  const bool found = intersect(shape, ray, kInfinity, hit, 5u);
  if (found) {
    if (!std::isfinite(hit.t) || !std::isfinite(hit.u) || !std::isfinite(hit.v)) {
      ++result.nan;
    } else {
      const SurfaceInteraction si = surface_at(shape, ray, hit);
      if (!finite(si.position) || !finite(si.geometric_normal) || !finite(si.shading_normal) ||
          !std::isfinite(si.uv.x) || !std::isfinite(si.uv.y))
        ++result.nan;
    }
  }
  bool wrong = false;
  if (found && is_ambiguous(hit.t) && (expected_count == 0 || hit.t < to_double(expected[0]))) {
    // an ambiguous root reported first: accepted
  } else if (found != (expected_count > 0)) {
    wrong = true;
  } else if (found) {
    const double e = judged_error(shape, generated, hit.t, expected[0]);
    if (e > 1e-3) {
      wrong = true;  // another root than the closest one
    } else {
      result.max_relative_t = std::max(result.max_relative_t, e);
      if (e > 1e-6) report_wrong_ray(ray, hit.t, expected, expected_count, ambiguous_count);
    }
  }
  if (wrong) {
    ++result.wrong;
    report_wrong_ray(ray, found ? hit.t : -1.0f, expected, expected_count, ambiguous_count);
  }

  HitRecord reported[8];
  const int n_reported = intersect_all(shape, ray, kInfinity, reported, 8, 5u);
  HitRecord all[8];
  int n = 0;
  for (int i = 0; i < n_reported; ++i)
    if (!is_ambiguous(reported[i].t)) all[n++] = reported[i];
  bool mismatch = n != expected_count;
  for (int i = 0; i < n && !mismatch; ++i) {
    if (!std::isfinite(all[i].t)) {
      ++result.nan;
      mismatch = true;
    } else if (i > 0 && all[i].t < all[i - 1].t) {
      mismatch = true;
    } else {
      const double e = judged_error(shape, generated, all[i].t, expected[i]);
      if (e > 1e-3) {
        mismatch = true;
      } else {
        result.max_relative_t = std::max(result.max_relative_t, e);
        if (e > 1e-6) report_wrong_ray(ray, all[i].t, expected, expected_count, ambiguous_count);
      }
    }
  }
  if (mismatch) ++result.all_hits_mismatch;
}

// Rays spawned from hits: one reflected (leaving on the side the ray came from) and one
// transmitted (entering), each from offset_ray_origin. A self-intersection is a hit within
// 1e-3 sizes of the spawn point that the reference does not have there.
template <typename Shape>
void evaluate_spawn(const Shape& shape, const Ray& ray, double scale, Rng& rng, RowResult& result,
                    float spawn_scale) {
  HitRecord hit;
  if (!intersect(shape, ray, kInfinity, hit, 5u)) return;
  const SurfaceInteraction si = surface_at(shape, ray, hit);
  if (!finite(si.position) || !finite(si.geometric_normal)) {
    ++result.nan;
    return;
  }
  for (int side = 0; side < 2; ++side) {
    const dvec3 n = dvec3(side == 0 ? si.geometric_normal : -si.geometric_normal);
    dvec3 direction = n + rng.unit_vector();
    if (glm::length(direction) < 1e-6) direction = n;
    direction = glm::normalize(direction);
    const Ray spawned = make_ray(
        dvec3(offset_ray_origin(si.position, vec3(n), spawn_scale, si.position_error)), direction);
    ++result.rays;
    HitRecord again;
    const bool found = intersect(shape, spawned, kInfinity, again, 5u);
    const ReferenceHits reference = reference_hits(shape, to_qray(spawned));
    if (reference.count > 0) ++result.reference_hits;
    if (!found) continue;
    if (!std::isfinite(again.t)) {
      ++result.nan;
      continue;
    }
    const double near = 1e-3 * scale / glm::length(dvec3(spawned.direction));
    if (again.t < near) {
      const bool real = reference.count > 0 && relative_error(again.t, reference.t[0]) < 1e-2;
      if (!real) ++result.wrong;
    } else if (reference.count > 0 && relative_error(again.t, reference.t[0]) < 1e-3) {
      result.max_relative_t =
          std::max(result.max_relative_t, relative_error(again.t, reference.t[0]));
    }
  }
}

// The double-precision triangle path (triangle_precise.hpp) as a shape of its own, so the
// same families run on it as on the float path the BVH uses.
struct PreciseTriangle {
  Triangle triangle;
};
bool intersect(const PreciseTriangle& p, const Ray& ray, float t_max, HitRecord& hit,
               std::uint32_t primitive) {
  return intersect_precise(p.triangle, ray, t_max, hit, primitive);
}
int intersect_all(const PreciseTriangle& p, const Ray& ray, float t_max, HitRecord* hits,
                  int max_hits, std::uint32_t primitive) {
  return intersect_all(p.triangle, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}
// The double path: the plain backward error of a flat shape.
double t_conditioning(const PreciseTriangle& p, const Ray& ray, double) {
  return flat_conditioning(triangle_normal(p.triangle), ray);
}
SurfaceInteraction surface_at(const PreciseTriangle& p, const Ray& ray, const HitRecord& hit) {
  return surface_at(p.triangle, ray, hit);
}
ReferenceHits reference_hits(const PreciseTriangle& p, const QRay& ray) {
  return reference_hits(p.triangle, ray);
}
BoundingSphere bounding_sphere(const PreciseTriangle& p) {
  return stress::bounding_sphere(p.triangle);
}
SurfacePoint sample_surface(const PreciseTriangle& p, Rng& rng) {
  return sample_surface(p.triangle, rng);
}
dvec3 shape_axis(const PreciseTriangle& p, Rng& rng) {
  return shape_axis(p.triangle, rng);
}
double surface_distance_bound(const PreciseTriangle& p, const dvec3& point) {
  return stress::surface_distance_bound(p.triangle, point);
}

// The torus with its quartic solved by Algorithm 1010 instead of root isolation: the same
// families on both show why the default is isolation.
struct Torus1010 {
  Torus torus;
};
bool intersect(const Torus1010& t, const Ray& ray, float t_max, HitRecord& hit,
               std::uint32_t primitive) {
  return detail::torus_candidates<detail::QuarticMethod::kAlgorithm1010>(
             t.torus, make_precise_ray(ray), t_max, true)
      .closest(ray.t_min, t_max, hit, primitive);
}
int intersect_all(const Torus1010& t, const Ray& ray, float t_max, HitRecord* hits, int max_hits,
                  std::uint32_t primitive) {
  return detail::torus_candidates<detail::QuarticMethod::kAlgorithm1010>(
             t.torus, make_precise_ray(ray), t_max)
      .all(ray.t_min, t_max, hits, max_hits, primitive);
}
SurfaceInteraction surface_at(const Torus1010& t, const Ray& ray, const HitRecord& hit) {
  return surface_at(t.torus, ray, hit);
}
ReferenceHits reference_hits(const Torus1010& t, const QRay& ray) {
  return stress::reference_hits(t.torus, ray);
}
BoundingSphere bounding_sphere(const Torus1010& t) {
  return stress::bounding_sphere(t.torus);
}
SurfacePoint sample_surface(const Torus1010& t, Rng& rng) {
  return stress::sample_surface(t.torus, rng);
}
dvec3 shape_axis(const Torus1010& t, Rng& rng) {
  return stress::shape_axis(t.torus, rng);
}
double surface_distance_bound(const Torus1010& t, const dvec3& point) {
  return stress::surface_distance_bound(t.torus, point);
}

// ---- the quartic solvers on their own: random quartics with known real roots (and
// complex pairs), coefficients rounded to double, compared with the quad-precision roots
// of the rounded polynomial. wrong = a different number of real roots; t = the largest
// error of a root relative to the largest root magnitude.
// kHugeRoot: three roots in [-1, 1] and one of magnitude 1e80 to 1e300; beyond ~1e102 no
// single power-of-two scaling of double holds both, and Algorithm 1010, which returned
// wrong roots when its scale^4 overflowed, then reported failure, hands them to isolation.
// Isolation solves them all: its critical points are found
// to full precision and its brackets halved in their exponent (RootSpan::kAnyMagnitude);
// to 1e-10 of the interval, as for the torus, it lost the small roots or stopped
// unconverged on every one. kHugeInterval: roots in [0.5, 2] plus a complex pair,
// isolated on [-1e300, 1e300], where the bracket search needed more than its iteration
// cap. In both, t is each root's error relative to max(|root|, 1).
enum class QuarticCase {
  kSeparated,
  kPairsComplex,
  kClosePairs,
  kNearDouble,
  kSpread1e4,
  kHugeRoot,
  kHugeInterval,
  kPairBesideRoot
};

// One solver answer against the expected roots (ascending): kSolverFailed counts as
// `failed`, a different count as wrong; per_root: each root's error relative to
// max(|root|, root_floor), and over 1e-6 is wrong; else relative to the largest root.
// Prints a wrong solver answer (TESSERA_STRESS_VERBOSE): the coefficients (ascending
// powers, exact hex), the roots found and the reference's.
void report_wrong_roots(const double* coefficients, int degree, const double* roots, int n,
                        const quad* expected, int expected_count) {
  static int printed = 0;
  if (!verbose_slot(printed)) return;
  std::printf("  wrong: coefficients");
  for (int i = 0; i <= degree; ++i) std::printf(" %a", coefficients[i]);
  std::printf("; found");
  for (int i = 0; i < n; ++i) std::printf(" %.17g", roots[i]);
  std::printf("; reference");
  for (int i = 0; i < expected_count; ++i) std::printf(" %.17g", to_double(expected[i]));
  std::printf("\n");
}

void score_roots(const double* roots, int n, const quad* expected, int expected_count,
                 bool per_root, RowResult& result, quad root_floor = 1) {
  ++result.rays;
  if (expected_count > 0) ++result.reference_hits;
  if (n == kSolverFailed) {  // an answer withheld is not a wrong answer
    ++result.failed;
    return;
  }
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(roots[i])) ++result.nan;
  if (n != expected_count) {
    ++result.wrong;
    return;
  }
  quad largest = 0;
  for (int i = 0; i < n; ++i) largest = std::max<quad>(largest, qabs(expected[i]));
  for (int i = 0; i < n; ++i) {
    const quad scale = per_root ? std::max<quad>(qabs(expected[i]), root_floor) : largest;
    const double error = to_double(qabs(roots[i] - expected[i]) / scale);
    // A root off by more than 1e-6 of its size is a wrong answer, not an inaccuracy.
    if (per_root && error > 1e-6) {
      ++result.wrong;
      return;
    }
    result.max_relative_t = std::max(result.max_relative_t, error);
  }
}

std::function<RowResult(int, std::uint64_t)> quartic_row(QuarticCase which, bool use_1010) {
  return [which, use_1010](int count, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    for (int k = 0; k < count; ++k) {
      quad c[5] = {1, 0, 0, 0, 0};
      const auto multiply = [&](quad q0, quad q1) {  // by x^2 + q1 x + q0
        quad n[5] = {0, 0, 0, 0, 0};
        for (int i = 0; i < 5; ++i) {
          if (c[i] == 0) continue;
          n[i] += c[i] * q0;
          if (i + 1 < 5) n[i + 1] += c[i] * q1;
          if (i + 2 < 5) n[i + 2] += c[i];
        }
        for (int i = 0; i < 5; ++i) c[i] = n[i];
      };
      quad known[4];  // the real roots the quartic was built from
      int known_count = 0;
      const auto real_pair = [&](double a, double b) {
        multiply(quad(a) * quad(b), -(quad(a) + quad(b)));
        known[known_count++] = a;
        known[known_count++] = b;
      };
      const auto complex_pair = [&](double re, double im) {
        multiply(quad(re) * re + quad(im) * im, -2 * quad(re));
      };
      const auto value = [&] { return rng.uniform(-1.0, 1.0); };
      switch (which) {
        case QuarticCase::kSeparated:
          real_pair(value(), value());
          real_pair(value(), value());
          break;
        case QuarticCase::kPairsComplex:
          real_pair(value(), value());
          complex_pair(value(), rng.log_uniform(1e-6, 1.0));
          break;
        case QuarticCase::kClosePairs:
        case QuarticCase::kNearDouble: {
          const double lo = which == QuarticCase::kClosePairs ? 1e-6 : 1e-9;
          const double hi = which == QuarticCase::kClosePairs ? 1e-3 : 1e-7;
          const double a = value(), b = value();
          real_pair(a, a + rng.log_uniform(lo, hi));
          real_pair(b, b + rng.log_uniform(lo, hi));
          break;
        }
        case QuarticCase::kSpread1e4:
          real_pair(value() * 1e-4, value() * 1e4);
          real_pair(value(), value() * 1e2);
          break;
        case QuarticCase::kHugeRoot:
          real_pair(value(), value());
          real_pair(value(), (rng.coin() ? 1.0 : -1.0) * rng.log_uniform(1e80, 1e300));
          break;
        case QuarticCase::kPairBesideRoot: {
          // A complex pair 1e-4..1e-2 beside a real root and 1e-7..1e-4 off the real axis:
          // the local extremum between them is a few ulps of the polynomial's terms from
          // zero, where Horner's sign is noise (two roots invented, or none).
          const double root = value();
          real_pair(root, value());
          complex_pair(root + (rng.coin() ? 1.0 : -1.0) * rng.log_uniform(1e-4, 1e-2),
                       rng.log_uniform(1e-7, 1e-4));
          break;
        }
        case QuarticCase::kHugeInterval:
          real_pair(rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0));
          complex_pair(value(), rng.log_uniform(1e-3, 1.0));
          break;
      }
      double coefficient[5];
      quad rounded[5];
      quad bound = 0;
      for (int i = 0; i < 5; ++i) {
        coefficient[i] = to_double(c[i]);
        rounded[i] = coefficient[i];
      }
      for (int i = 0; i < 4; ++i) bound = std::max<quad>(bound, qabs(rounded[i] / rounded[4]));
      bound += 1;  // Cauchy: every root is inside [-bound, bound]
      // Widened before it is rounded to double: with a huge root H and small roots summing
      // to s in (-1, 0), |c3| = H + s rounds to H and the bound to H itself, an interval
      // that ends on the root (the rounded polynomial's root may lie an ulp beyond it).
      bound *= 1 + 1e-12;
      if (which == QuarticCase::kHugeInterval) bound = 1e300;
      quad expected[4];
      const bool per_root = which == QuarticCase::kHugeRoot || which == QuarticCase::kHugeInterval;
      int expected_count;
      if (per_root) {
        // The roots it was built from (rounding the coefficients moves these well-separated
        // roots by ~1e-16 of their size): the quad reference's regula falsi cannot shrink
        // brackets reaching 1e300 within its own iteration cap.
        expected_count = known_count;
        for (int i = 0; i < known_count; ++i) {  // insertion sort, ascending
          int j = i;
          for (; j > 0 && expected[j - 1] > known[i]; --j) expected[j] = expected[j - 1];
          expected[j] = known[i];
        }
      } else {
        expected_count = reference_roots(rounded, 4, -bound, bound, expected);
      }
      double roots[4];
      int n;
      if (use_1010) {
        n = solve_quartic(coefficient[4], coefficient[3], coefficient[2], coefficient[1],
                          coefficient[0], roots);
      } else {
        const Polynomial<4, double> p{
            {coefficient[0], coefficient[1], coefficient[2], coefficient[3], coefficient[4]}};
        n = roots_in_interval(p, -to_double(bound), to_double(bound), roots);
      }
      const long wrong_before = result.wrong;
      score_roots(roots, n, expected, expected_count, per_root, result);
      if (result.wrong != wrong_before)
        report_wrong_roots(coefficient, 4, roots, n, expected, expected_count);
    }
    return result;
  };
}

// The cubic solver alone, the same way: one real root times a real or complex pair.
// kHugeRoot: two roots in [-1, 1] and one of 1e80..1e300 (the depressed form's shift^3
// overflowed and the solver returned NaN); kSpread: roots 1e-150..1e-50, 0.5..2, and
// 1e50..1e150, each to be found relative to its own size (they came back as one infinite
// root). In both, t is each root's error relative to max(|root|, 1), or |root| (kSpread).
enum class CubicCase { kSeparated, kPairComplex, kSpread1e4, kHugeRoot, kSpread };

std::function<RowResult(int, std::uint64_t)> cubic_row(CubicCase which) {
  return [which](int count, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    for (int k = 0; k < count; ++k) {
      const auto value = [&] { return rng.uniform(-1.0, 1.0); };
      const auto sign = [&] { return rng.coin() ? 1.0 : -1.0; };
      double real = value();
      double q1 = 0, q0 = 0;  // the other factor, x^2 + q1 x + q0
      quad known[3];
      int known_count = 0;
      const auto real_pair = [&](double a, double b) {
        q1 = to_double(-(quad(a) + quad(b)));
        q0 = to_double(quad(a) * quad(b));
        known[known_count++] = a;
        known[known_count++] = b;
      };
      switch (which) {
        case CubicCase::kSeparated:
          real_pair(value(), value());
          break;
        case CubicCase::kPairComplex: {
          const double re = value(), im = rng.log_uniform(1e-6, 1.0);
          q1 = -2 * re;
          q0 = to_double(quad(re) * re + quad(im) * im);
          break;
        }
        case CubicCase::kSpread1e4:
          real *= 1e-4;
          real_pair(value(), value() * 1e4);
          break;
        case CubicCase::kHugeRoot:
          real_pair(value(), sign() * rng.log_uniform(1e80, 1e300));
          break;
        case CubicCase::kSpread:  // each root's error relative to itself
          real = sign() * rng.uniform(0.5, 2.0);
          real_pair(sign() * rng.log_uniform(1e-150, 1e-50), sign() * rng.log_uniform(1e50, 1e150));
          break;
      }
      known[known_count++] = real;
      // (x - real)(x^2 + q1 x + q0) in quad, each coefficient rounded once to double; the
      // pair's coefficients are exact doubles, so the known roots are the pair's roots of
      // that rounded factor to ~1e-16 of their size.
      const quad c_quad[4] = {-quad(real) * q0, quad(q0) - quad(real) * q1, quad(q1) - real, 1};
      double coefficient[4];
      quad rounded[4];
      for (int i = 0; i < 4; ++i) {
        coefficient[i] = to_double(c_quad[i]);
        rounded[i] = coefficient[i];
      }
      quad expected[3];
      const bool per_root = which == CubicCase::kHugeRoot || which == CubicCase::kSpread;
      int expected_count;
      if (per_root) {
        expected_count = known_count;
        sort_ascending(known, known_count);
        for (int i = 0; i < known_count; ++i) expected[i] = known[i];
      } else {
        quad bound = 0;
        for (int i = 0; i < 3; ++i) bound = std::max<quad>(bound, qabs(rounded[i]));
        bound = (bound + 1) * (1 + 1e-12);
        expected_count = reference_roots(rounded, 3, -bound, bound, expected);
      }
      double roots[3];
      const int n =
          solve_cubic(coefficient[3], coefficient[2], coefficient[1], coefficient[0], roots);
      const long wrong_before = result.wrong;
      score_roots(roots, n, expected, expected_count, per_root, result,
                  which == CubicCase::kSpread ? 0 : 1);
      if (result.wrong != wrong_before)
        report_wrong_roots(coefficient, 3, roots, n, expected, expected_count);
    }
    return result;
  };
}

// ---- shapes, built around a centre at a scale with a random orientation

struct Placement {
  dvec3 center{0.0};
  double scale = 1.0;
};

Sphere make_sphere(const Placement& p, Rng&) {
  return Sphere{vec3(p.center), static_cast<float>(p.scale), 0};
}
Plane make_plane(const Placement& p, Rng& rng) {
  return Plane::make(vec3(p.center), vec3(rng.unit_vector()), 0, static_cast<float>(p.scale));
}
Disk make_disk(const Placement& p, Rng& rng) {
  return Disk::make(vec3(p.center), vec3(rng.unit_vector()), static_cast<float>(p.scale), 0);
}
Disk make_annulus(const Placement& p, Rng& rng) {
  return Disk::make(vec3(p.center), vec3(rng.unit_vector()), static_cast<float>(p.scale), 0,
                    static_cast<float>(0.4 * p.scale));
}
Quad make_quad(const Placement& p, Rng& rng) {
  const dvec3 n = rng.unit_vector();
  const dvec3 u = rng.perpendicular_unit(n) * (p.scale * rng.uniform(0.5, 1.5));
  dvec3 v = glm::normalize(glm::cross(n, u) + rng.perpendicular_unit(n) * 0.3) *
            (p.scale * rng.uniform(0.5, 1.5));
  return Quad::make(vec3(p.center - 0.5 * u - 0.5 * v), vec3(u), vec3(v), 0);
}
Triangle make_triangle(const Placement& p, Rng& rng) {
  for (;;) {
    const dvec3 a = rng.unit_vector(), b = rng.unit_vector(), c = rng.unit_vector();
    if (glm::length(glm::cross(b - a, c - a)) < 0.2) continue;  // keep it a proper triangle
    return Triangle{vec3(p.center + a * p.scale), vec3(p.center + b * p.scale),
                    vec3(p.center + c * p.scale), 0};
  }
}
Cylinder make_cylinder(const Placement& p, Rng& rng, bool capped) {
  const dvec3 axis = rng.unit_vector();
  return Cylinder::make(vec3(p.center - axis * (0.5 * p.scale)), vec3(axis),
                        static_cast<float>(0.5 * p.scale), static_cast<float>(p.scale), capped, 0);
}
Cone make_cone(const Placement& p, Rng& rng, double top_fraction, bool capped) {
  const dvec3 axis = rng.unit_vector();
  return Cone::make(
      vec3(p.center - axis * (0.5 * p.scale)), vec3(axis), static_cast<float>(0.6 * p.scale),
      static_cast<float>(top_fraction * 0.6 * p.scale), static_cast<float>(p.scale), capped, 0);
}
Torus make_torus(const Placement& p, Rng& rng, double minor_over_major) {
  const double R = p.scale / (1.0 + minor_over_major);
  return Torus::make(vec3(p.center), vec3(rng.unit_vector()), static_cast<float>(R),
                     static_cast<float>(R * minor_over_major), 0);
}
template <typename Shape>
Instance<Shape> make_instance(const Shape& object, const Placement& p, Rng& rng) {
  const dvec3 scale(rng.log_uniform(0.5, 2.0), rng.log_uniform(0.5, 2.0),
                    rng.log_uniform(0.5, 2.0));
  Instance<Shape> instance;
  Instance<Shape>::make(
      object,
      AffineTransform::from_trs(p.center, rng.unit_vector(), rng.uniform(0.0, kTwoPi), scale),
      instance);
  return instance;
}

SdfBox make_sdf_box(const Placement& p, Rng& rng, double rounding) {
  const dvec3 h =
      dvec3(rng.uniform(0.5, 1.0), rng.uniform(0.5, 1.0), rng.uniform(0.5, 1.0)) * (0.6 * p.scale);
  const double r = rounding * glm::min(h.x, glm::min(h.y, h.z));
  return SdfBox{vec3(p.center), vec3(h), static_cast<float>(r), 0};
}
SdfTorus make_sdf_torus(const Placement& p, Rng& rng) {
  return SdfTorus{vec3(p.center), vec3(rng.unit_vector()), static_cast<float>(0.8 * p.scale),
                  static_cast<float>(0.2 * p.scale), 0};
}
SdfCapsule make_sdf_capsule(const Placement& p, Rng& rng) {
  const dvec3 half = rng.unit_vector() * (0.5 * p.scale);
  return SdfCapsule{vec3(p.center - half), vec3(p.center + half), static_cast<float>(0.3 * p.scale),
                    0};
}

// ---- rows

enum class Where { kOrigin, kOffset, kTiny, kHuge };

Placement place(Where where, Rng& rng) {
  switch (where) {
    case Where::kOrigin:
      return {dvec3(0.0), 1.0};
    case Where::kOffset:
      return {rng.unit_vector() * rng.log_uniform(1e2, 1e6), 1.0};
    case Where::kTiny:
      return {rng.unit_vector() * rng.uniform(0.0, 1e-3), 1e-4};
    case Where::kHuge:
      return {rng.unit_vector() * rng.uniform(0.0, 1e4), 1e4};
  }
  return {};
}

template <typename Make>
std::function<RowResult(int, std::uint64_t)> ray_row(Make make, Family family, Where where) {
  return [make, family, where](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    for (int i = 0; i < rays; ++i) {
      const Placement p = place(where, rng);
      const auto shape = make(p, rng);
      evaluate_ray(shape, generate(shape, family, p.scale, rng), result);
    }
    return result;
  };
}

// Shapes of `size` at `offset` from the origin. A size below 1 stands for a scene that
// small, whose spawned rays the renderer offsets at its spawn_scale_for_extent.
template <typename Make>
std::function<RowResult(int, std::uint64_t)> spawn_row(Make make, double offset,
                                                       double size = 1.0) {
  return [make, offset, size](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    for (int i = 0; i < rays; ++i) {
      const Placement p{offset > 0.0 ? rng.unit_vector() * offset : dvec3(0.0), size};
      const auto shape = make(p, rng);
      float spawn_scale = 1.0f;
      if constexpr (requires { stress::bounding_sphere(shape); }) {
        if (size < 1.0) {
          const BoundingSphere bound = stress::bounding_sphere(shape);
          spawn_scale =
              spawn_scale_for_extent(static_cast<float>(glm::length(bound.center) + bound.radius));
        }
      }
      evaluate_spawn(shape, generate(shape, Family::kRandom, p.scale, rng).ray, p.scale, rng,
                     result, spawn_scale);
    }
    return result;
  };
}

// ---- watertightness: every ray aimed exactly at a shared edge or vertex of a closed or
// edge-sharing mesh, and crossing the surface there, must hit at least one of its
// triangles. Rays that only touch an edge (a silhouette edge seen from the ray's side)
// may legitimately miss after rounding, so they are not generated: closed meshes are
// star-shaped around `inside` and rays run along lines through `inside`; the open meshes
// are crossed at angles well away from their faces' planes.

// Rounds to float through an opaque call (see make_ray).
[[gnu::noinline]] dvec3 to_float_point(const dvec3& p) {
  return dvec3(vec3(p));
}

struct Mesh {
  std::vector<Triangle> triangles;
  std::vector<dvec3> targets;   // vertices and points on shared edges (float values)
  dvec3 inside{0.0};            // closed meshes: a point they are star-shaped around
  dvec3 normal{0.0, 0.0, 1.0};  // open meshes: the direction rays cross them along (+-30 deg)
  bool closed = false;
};

void add_edge_targets(Mesh& mesh, const dvec3& a, const dvec3& b, Rng& rng) {
  mesh.targets.push_back(a);
  mesh.targets.push_back(b);
  mesh.targets.push_back(to_float_point(0.5 * (a + b)));
  mesh.targets.push_back(to_float_point(a + rng.uniform() * (b - a)));
}

// Bipyramid over an n-gon: 2n triangles, every edge shared by exactly two of them. The
// ring's height jitter is proportional to its spacing, so the faces stay far from the
// centre and the mesh is star-shaped around it.
Mesh make_bipyramid(int n, const dvec3& center, double scale, Rng& rng) {
  Mesh mesh;
  mesh.closed = true;
  mesh.inside = center;
  const dvec3 top = to_float_point(center + dvec3(0, 0, scale));
  const dvec3 bottom = to_float_point(center - dvec3(0, 0, scale * rng.uniform(0.5, 1.5)));
  const double phase = rng.uniform(0.0, kTwoPi);
  const double jitter = 0.2 * kTwoPi / n;
  std::vector<dvec3> ring(n);
  for (int i = 0; i < n; ++i) {
    const double a = phase + kTwoPi * i / n;
    ring[i] = to_float_point(center +
                             dvec3(std::cos(a), std::sin(a), rng.uniform(-jitter, jitter)) * scale);
  }
  for (int i = 0; i < n; ++i) {
    const dvec3& a = ring[i];
    const dvec3& b = ring[(i + 1) % n];
    mesh.triangles.push_back(Triangle{vec3(a), vec3(b), vec3(top), 0});
    mesh.triangles.push_back(Triangle{vec3(b), vec3(a), vec3(bottom), 0});
    add_edge_targets(mesh, a, b, rng);
    add_edge_targets(mesh, a, top, rng);
    add_edge_targets(mesh, a, bottom, rng);
  }
  return mesh;
}

// Planar fan of n triangles around a centre vertex (a disk), crossed from either side.
Mesh make_fan(int n, const dvec3& center, double scale, Rng& rng) {
  Mesh mesh;
  mesh.normal = rng.unit_vector();
  const AxisFrame f = AxisFrame::from_axis(vec3(mesh.normal));
  const dvec3 c = to_float_point(center);
  std::vector<dvec3> ring(n);
  for (int i = 0; i < n; ++i) {
    const double a = kTwoPi * i / n;
    ring[i] = to_float_point(center + (f.u * std::cos(a) + f.v * std::sin(a)) * scale);
  }
  for (int i = 0; i < n; ++i) {
    const dvec3& a = ring[i];
    const dvec3& b = ring[(i + 1) % n];
    mesh.triangles.push_back(Triangle{vec3(c), vec3(a), vec3(b), 0});
    // Interior shared edges (centre to rim vertex) and the centre vertex. The rim is the
    // border, where a ray rounded to float may pass just outside: kept 1% away from it.
    mesh.targets.push_back(c);
    mesh.targets.push_back(to_float_point(0.5 * (c + a)));
    mesh.targets.push_back(to_float_point(c + rng.uniform(0.0, 0.99) * (a - c)));
  }
  return mesh;
}

// Height-field grid of k x k cells split into triangles along alternating diagonals, with
// slopes below ~22 degrees, crossed within 30 degrees of vertical.
Mesh make_grid(int k, const dvec3& center, double scale, Rng& rng) {
  Mesh mesh;
  const double cell = 2.0 * scale / k;
  std::vector<dvec3> v((k + 1) * (k + 1));
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i)
      v[j * (k + 1) + i] = to_float_point(
          center + dvec3(cell * i - scale, cell * j - scale, 0.2 * cell * rng.uniform(-1.0, 1.0)));
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      const dvec3 a = v[j * (k + 1) + i], b = v[j * (k + 1) + i + 1];
      const dvec3 c = v[(j + 1) * (k + 1) + i + 1], d = v[(j + 1) * (k + 1) + i];
      // Targets on interior edges only (the diagonal, and the left and bottom edges when
      // they are not on the border), plus interior vertices.
      const auto on_edge = [&](const dvec3& p, const dvec3& q) {
        mesh.targets.push_back(to_float_point(0.5 * (p + q)));
        mesh.targets.push_back(to_float_point(p + rng.uniform(0.01, 0.99) * (q - p)));
      };
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back(Triangle{vec3(a), vec3(b), vec3(c), 0});
        mesh.triangles.push_back(Triangle{vec3(a), vec3(c), vec3(d), 0});
        on_edge(a, c);
      } else {
        mesh.triangles.push_back(Triangle{vec3(a), vec3(b), vec3(d), 0});
        mesh.triangles.push_back(Triangle{vec3(b), vec3(c), vec3(d), 0});
        on_edge(b, d);
      }
      if (i > 0) on_edge(a, d);
      if (j > 0) on_edge(a, b);
      if (i > 0 && j > 0) mesh.targets.push_back(a);
    }
  }
  return mesh;
}

// A ray must hit some triangle (brute force over the mesh, float watertight test).
bool mesh_hit(const Mesh& mesh, const Ray& ray) {
  const WatertightRay wr(ray.direction);
  HitRecord hit;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    if (intersect(mesh.triangles[i], ray, wr, kInfinity, hit, static_cast<std::uint32_t>(i)))
      return true;
  return false;
}

// At offset 1e5 float spacing is 2^-7: the meshes are made 10x larger there so that
// rounding their vertices cannot fold neighbouring triangles over each other.
std::function<RowResult(int, std::uint64_t)> watertight_row(int kind, double offset) {
  return [kind, offset](int rays, std::uint64_t seed) {
    const double scale = offset > 0.0 ? 10.0 : 1.0;
    Rng rng(seed);
    RowResult result;
    while (result.rays < rays) {
      const dvec3 center = offset > 0.0 ? rng.unit_vector() * offset : dvec3(0.0);
      const int n = static_cast<int>(std::lround(rng.log_uniform(4.0, 1024.0)));
      const Mesh mesh = kind == 0   ? make_fan(n, center, scale, rng)
                        : kind == 1 ? make_bipyramid(std::max(3, n / 2), center, scale, rng)
                                    : make_grid(std::max(2, static_cast<int>(std::sqrt(n / 2.0))),
                                                center, scale, rng);
      for (int k = 0; k < 64 && result.rays < rays; ++k) {
        const dvec3 target =
            mesh.targets[static_cast<std::size_t>(rng.uniform(0.0, 1.0) * mesh.targets.size()) %
                         mesh.targets.size()];
        dvec3 origin;
        if (mesh.closed) {
          // From near the centre outwards, or from outside inwards along the same line.
          const dvec3 radial = target - mesh.inside;
          origin = rng.coin() ? mesh.inside + rng.in_ball(0.01 * scale)
                              : mesh.inside + radial * rng.uniform(1.5, 5.0);
        } else {
          dvec3 across;
          do {
            across = rng.unit_vector();
          } while (std::fabs(glm::dot(across, mesh.normal)) < 0.866);
          origin = target + across * (scale * rng.uniform(0.5, 5.0));
        }
        const dvec3 direction = target - origin;
        if (glm::length(direction) == 0.0) continue;
        const Ray ray = make_ray(origin, direction);
        ++result.rays;
        ++result.reference_hits;
        if (!mesh_hit(mesh, ray)) ++result.wrong;
      }
    }
    return result;
  };
}

// ---- degenerate triangles: zero area (three collinear vertices, rounded to float;
// two coincident vertices) and near-zero area (a sliver whose height is 2^-24 of its
// length), 1e-4 to 1e4 in size, randomly oriented; rays aimed at points of them from 0.1 to
// 1e4 sizes away. The reference has no hit (there is no surface): any hit reported by the
// float test or the double one is wrong. Before is_degenerate, 20% of the collinear rays and
// 25% of the sliver rays were reported as hits (noise over noise in the float test).
enum class DegenerateKind { kCollinear, kCoincident, kSliver };

std::function<RowResult(int, std::uint64_t)> degenerate_triangle_row(DegenerateKind kind) {
  return [kind](int rays, std::uint64_t seed) {
    Rng rng(seed);
    RowResult result;
    while (result.rays < rays) {
      const double scale = rng.log_uniform(1e-4, 1e4);
      const dvec3 p0 = to_float_point(rng.in_ball(scale));
      const dvec3 along = rng.unit_vector() * scale;
      dvec3 p1 = p0, p2 = p0;
      switch (kind) {
        case DegenerateKind::kCollinear:
          p1 = to_float_point(p0 + along * rng.uniform(0.1, 1.0));
          p2 = to_float_point(p0 + along * rng.uniform(-1.0, 2.0));
          break;
        case DegenerateKind::kCoincident:
          p1 = p0;
          p2 = to_float_point(p0 + along);
          break;
        case DegenerateKind::kSliver: {
          dvec3 across = glm::cross(along, rng.unit_vector());
          across *= 0x1p-24 * glm::length(along) / glm::length(across);
          p1 = to_float_point(p0 + along);
          p2 = to_float_point(p0 + 0.5 * along + across);
          break;
        }
      }
      const Triangle tri{vec3(p0), vec3(p1), vec3(p2), 0};
      if (!is_degenerate(tri)) continue;  // rounding made it a (thin) real triangle
      for (int k = 0; k < 64 && result.rays < rays; ++k) {
        const double w1 = rng.uniform(), w2 = rng.uniform() * (1.0 - w1);
        const dvec3 target = to_float_point(p0 + w1 * (p1 - p0) + w2 * (p2 - p0));
        const dvec3 origin = target + rng.unit_vector() * (scale * rng.log_uniform(0.1, 1e4));
        const Ray ray = make_ray(origin, target - origin);
        ++result.rays;
        HitRecord hit;
        if (intersect(tri, ray, kInfinity, hit, 0u) ||
            intersect_precise(tri, ray, kInfinity, hit, 0u))
          ++result.wrong;
      }
    }
    return result;
  };
}

// The bounds each row asserts. Every row not listed must be exact: no wrong decision, no
// all-hits mismatch, t within 1e-7 relative (the float rounding of a double root is at most
// 2^-24 = 6e-8; flat shapes' errors are their backward errors, and a root near the start
// of a ray leaving the surface is judged against its close pair's conditioning: see
// t_conditioning and start_pair_conditioning). NaN is never
// allowed. The numbers come from tessera-stress --seed 0..59 and 100..159 through
// tests/stress/derive_bounds.py, whose docstring gives the method (seeds 100..129, then
// 130..159, were held out at first, failed rows the seeds before never had, and were then
// added): a row that erred at some seed allows the count a Poisson rate at its 99.9% upper
// limit exceeds with probability 1e-5; a row that never erred stays exact; a t bound is
// twice the largest error measured. (Until 6 December they were the worst case of seeds
// 0..4 rounded up, and 14 of 23 seeds between 5 and 59 failed a row.)
struct BoundsException {
  const char* surface;
  const char* family;
  Bounds bounds;
};
const BoundsException kExceptions[] = {
    // The float Woop test the BVH uses for meshes: watertight, but its decisions carry
    // float rounding of the coordinates relative to the origin (a 1-unit triangle seen from
    // 1e6 units: edge functions uncertain by ~6% of its size), and no start-surface rule
    // (spawned rays are offset instead). Its hit lies within a few 2^-24 of the vertices'
    // reach from the origin (t_conditioning; at most 2.9e-7 over 150 seeds).
    // The double path ("triangle (double)") meets the default bounds on the same rays.
    {"triangle (float)", "random near", {3, 1e-6, 3}},
    {"triangle (float)", "far 1e2-1e4", {8, 1e-6, 8}},
    {"triangle (float)", "far 1e5-1e6", {136, 1e-6, 136}},
    {"triangle (float)", "grazing", {14, 1e-6, 14}},
    {"triangle (float)", "axis-aligned", {0, 1e-6, 0}},
    {"triangle (float)", "along axis", {0, 1e-6, 0}},
    {"triangle (float)", "origin on surface", {2000, 1e-7, 2000}},
    {"triangle (float)", "offset 1e2-1e6", {0, 1e-6, 0}},
    {"triangle (float)", "tiny (size 1e-4)", {0, 1e-6, 0}},
    {"triangle (float)", "huge (size 1e4)", {0, 1e-6, 0}},
    // Singular points: the horn torus's centre (the tube meets itself; an origin there
    // sits within 3e-8 of the other sheet) and the spindle torus's cusps on the axis (apple
    // and lemon roots within the ray's distance from the axis, below double resolution).
    {"torus horn r=R", "origin on surface", {8, 2e-3, 8}},
    {"torus spindle r=1.5R", "random near", {0, 5e-7, 0}},
    {"torus spindle r=1.5R", "along axis", {17, 1e-7, 24}},
    // Sphere tracing (bounded: 512 steps, a step floor growing from 1e-6 of the size):
    // crossings with a chord shorter than the floor are stepped over. The plain box's
    // "grazing" and "axis-aligned" rays are mostly such: surface samples land on edges and
    // corners (the nearest point of the box to much of space), so a tangent there clips a
    // chord of ~1e-7, and axis-aligned rays through face points run inside the face's own
    // plane, touching the surface without crossing it. Other families meet such chords
    // now and then (a few in 2,000 rays at some seeds).
    {"sdf box", "random near", {36, 1e-7, 36}},
    {"sdf box", "far 1e2-1e4", {6, 1e-7, 6}},
    {"sdf box", "grazing", {1350, 1e-7, 1350}},
    {"sdf box", "axis-aligned", {1080, 1e-7, 1080}},
    {"sdf box", "origin on surface", {16, 1e-7, 16}},
    {"sdf box", "offset 1e2-1e6", {5, 1e-7, 5}},
    {"sdf rounded box", "grazing", {53, 1e-7, 53}},
    {"sdf rounded box", "tangent", {147, 1e-7, 147}},
    {"sdf rounded box", "tangent +-1e-6", {4, 1e-7, 4}},
    {"sdf rounded box", "axis-aligned", {708, 1e-7, 708}},
    {"sdf rounded box", "origin on surface", {15, 1e-7, 15}},
    {"sdf torus", "random near", {0, 1e-7, 4}},
    {"sdf torus", "grazing", {46, 1e-7, 83}},
    {"sdf torus", "tangent", {98, 1e-7, 200}},
    {"sdf torus", "tangent +-1e-6", {4, 1e-7, 10}},
    {"sdf torus", "axis-aligned", {4, 1e-7, 4}},
    {"sdf torus", "origin on surface", {14, 1e-7, 14}},
    {"sdf capsule", "random near", {3, 1e-7, 3}},
    {"sdf capsule", "grazing", {58, 1e-7, 58}},
    {"sdf capsule", "tangent", {152, 1e-7, 152}},
    {"sdf capsule", "tangent +-1e-6", {4, 1e-7, 4}},
    {"sdf capsule", "axis-aligned", {4, 1e-7, 4}},
    {"sdf capsule", "origin on surface", {13, 1e-7, 13}},
    {"sdf capsule", "offset 1e2-1e6", {4, 1e-7, 4}},
    // The quartic solvers alone (t here is the root error relative to the largest root).
    // Close pairs: a root pair 1e-6 apart is conditioned like sqrt(eps); when both pairs
    // also fall close together the count can flip. Near-double pairs (1e-9..1e-7 apart):
    // the rounded polynomial's real/complex split is decided by its last bits. Isolation
    // decides the signs at its critical points by compensated Horner where plain Horner
    // cannot (sign_reliable_value), and matches the quad reference on all but 0-2 of 4000
    // (seeds 0-59; 1111-1204 wrong before); Algorithm 1010 gets about a quarter wrong.
    {"quartic: isolation", "4 real, separated", {0, 1e-8, 0}},
    {"quartic: isolation", "2 real + complex pair", {0, 1e-5, 0}},
    // Algorithm 1010 over seeds 0..299 (2026-12-07, its rows alone): 7 seeds had one wrong
    // count on a complex pair close to the axis (seed 167's case, in the README), and a
    // separated root's error reached 1.06e-8 of the largest root.
    {"quartic: Alg. 1010", "2 real + complex pair", {3, 2e-5, 0}},
    {"quartic: Alg. 1010", "4 real, separated", {0, 5e-8, 0}},
    {"quartic: isolation", "2 close pairs 1e-6..1e-3", {12, 2e-4, 12}},
    {"quartic: Alg. 1010", "2 close pairs 1e-6..1e-3", {15, 5e-4, 15}},
    {"quartic: isolation", "near-double 1e-9..1e-7", {6, 2e-4, 6}},
    {"quartic: isolation", "complex pair beside a root", {0, 2e-4, 0}},
    {"quartic: Alg. 1010", "near-double 1e-9..1e-7", {1800, 100.0, 1800}},
    {"quartic: isolation", "magnitudes 1e-4..1e4", {0, 1e-11, 0}},
    {"quartic: Alg. 1010", "magnitudes 1e-4..1e4", {0, 1e-11, 0}},
    // A complex pair 1e-6..1 off the axis beside the real root makes that root
    // ill-conditioned, as in the quartic's row (measured 1.3e-7 at the table's seed); when
    // the pair also lies within ~1e-5 of the real root, the three are a cluster whose
    // real/complex split the rounded coefficients no longer decide (1 wrong count in
    // 240,000 cubics over seeds 0..59).
    {"cubic", "1 real + complex pair", {4, 1e-5, 0}},
};

Bounds bounds_for(const std::string& surface, const std::string& family) {
  for (const BoundsException& e : kExceptions)
    if (surface == e.surface && family == e.family) return e.bounds;
  return Bounds{0, 1e-7, 0};
}

}  // namespace

bool passes(const Row& row, const RowResult& r) {
  return r.nan == 0 && r.wrong <= row.bounds.max_wrong &&
         r.max_relative_t <= row.bounds.max_relative_t &&
         r.all_hits_mismatch <= row.bounds.max_all_hits_mismatch;
}

std::string table_header() {
  char line[256];
  std::snprintf(line, sizeof line, "%-22s %-24s %7s %7s %7s %7s %5s %11s %6s  %s", "surface",
                "case family", "rays", "ref.hit", "wrong", "all-hit", "NaN", "max rel t", "failed",
                "bounds (wrong / all / t)");
  return line;
}

std::string table_line(const Row& row, const RowResult& r) {
  char line[320];
  std::snprintf(line, sizeof line,
                "%-22s %-24s %7ld %7ld %7ld %7ld %5ld %11.2e %6ld  <=%ld / <=%ld / <=%.0e  %s",
                row.surface.c_str(), row.family.c_str(), r.rays, r.reference_hits, r.wrong,
                r.all_hits_mismatch, r.nan, r.max_relative_t, r.failed, row.bounds.max_wrong,
                row.bounds.max_all_hits_mismatch, row.bounds.max_relative_t,
                passes(row, r) ? "ok" : "FAIL");
  return line;
}

std::vector<Row> all_rows() {
  std::vector<Row> rows;
  std::vector<Row> later;  // appended at the end (add_families)
  const auto add = [&](const std::string& surface, const std::string& family,
                       std::function<RowResult(int, std::uint64_t)> run, int rays = 4000) {
    rows.push_back(Row{surface, family, rays, bounds_for(surface, family), std::move(run)});
  };

  const std::vector<Family> curved = {
      Family::kRandom,      Family::kFarMid,    Family::kFarExtreme,
      Family::kGrazing,     Family::kTangent,   Family::kNearTangent,
      Family::kAxisAligned, Family::kAlongAxis, Family::kOnSurface};
  const std::vector<Family> flat = {Family::kRandom,    Family::kFarMid,   Family::kFarExtreme,
                                    Family::kGrazing,   Family::kParallel, Family::kAxisAligned,
                                    Family::kAlongAxis, Family::kOnSurface};
  const auto add_families = [&](const std::string& surface, auto make,
                                const std::vector<Family>& families) {
    for (Family f : families) add(surface, family_name(f), ray_row(make, f, Where::kOrigin));
    add(surface, "offset 1e2-1e6", ray_row(make, Family::kRandom, Where::kOffset));
    add(surface, "tiny (size 1e-4)", ray_row(make, Family::kRandom, Where::kTiny));
    add(surface, "huge (size 1e4)", ray_row(make, Family::kRandom, Where::kHuge));
    for (double offset : {1e1, 1e3, 1e5}) {
      char name[64];
      std::snprintf(name, sizeof name, "spawn @%.0e", offset);
      add(surface, name, spawn_row(make, offset), 2000);
    }
    add(surface, "spawn, size 1e-3", spawn_row(make, 0.0, 1e-3), 2000);
    // Kilometres across at the origin: hit points near the origin computed from corners far
    // from it (a terrain's ground triangle). Added after every other row, so the rows before
    // them keep the seeds (the row's index) they had.
    later.push_back(Row{surface, "spawn, size 1e4", 2000, bounds_for(surface, "spawn, size 1e4"),
                        spawn_row(make, 0.0, 1e4)});
  };

  add_families("sphere", make_sphere, curved);
  add_families("plane", make_plane, flat);
  add_families("disk", make_disk, flat);
  add_families("annulus", make_annulus, flat);
  add_families("quad", make_quad, flat);
  add_families("triangle (float)", make_triangle, flat);
  add_families(
      "triangle (double)",
      [](const Placement& p, Rng& r) { return PreciseTriangle{make_triangle(p, r)}; }, flat);
  add_families(
      "cylinder (capped)", [](const Placement& p, Rng& r) { return make_cylinder(p, r, true); },
      curved);
  add_families(
      "cylinder (open)", [](const Placement& p, Rng& r) { return make_cylinder(p, r, false); },
      curved);
  add_families(
      "cone (capped)", [](const Placement& p, Rng& r) { return make_cone(p, r, 0.0, true); },
      curved);
  add_families(
      "frustum (open)", [](const Placement& p, Rng& r) { return make_cone(p, r, 0.4, false); },
      curved);
  add_families(
      "torus r/R=0.25", [](const Placement& p, Rng& r) { return make_torus(p, r, 0.25); }, curved);
  for (double ratio : {1e-2, 1e-3, 1e-5}) {
    char name[64];
    std::snprintf(name, sizeof name, "torus r/R=%.0e", ratio);
    const auto make = [ratio](const Placement& p, Rng& r) { return make_torus(p, r, ratio); };
    for (Family f :
         {Family::kRandom, Family::kFarMid, Family::kFarExtreme, Family::kGrazing, Family::kTangent,
          Family::kNearTangent, Family::kAlongAxis, Family::kOnSurface})
      add(name, family_name(f), ray_row(make, f, Where::kOrigin));
    add(name, "offset 1e2-1e6", ray_row(make, Family::kRandom, Where::kOffset));
  }
  add_families(
      "torus horn r=R", [](const Placement& p, Rng& r) { return make_torus(p, r, 1.0); }, curved);
  add_families(
      "torus spindle r=1.5R", [](const Placement& p, Rng& r) { return make_torus(p, r, 1.5); },
      curved);

  const auto add_instanced = [&](const std::string& surface, auto make_object) {
    const auto make = [make_object](const Placement& p, Rng& r) {
      return make_instance(make_object(Placement{dvec3(0.0), p.scale}, r), p, r);
    };
    for (Family f : {Family::kRandom, Family::kFarMid, Family::kGrazing, Family::kOnSurface})
      add(surface, family_name(f), ray_row(make, f, Where::kOrigin));
    add(surface, "offset 1e2-1e6", ray_row(make, Family::kRandom, Where::kOffset));
    add(surface, "spawn @1e+03", spawn_row(make, 1e3), 2000);
  };
  add_instanced("instance(sphere)", make_sphere);
  add_instanced("instance(triangle)", make_triangle);
  add_instanced("instance(cylinder)",
                [](const Placement& p, Rng& r) { return make_cylinder(p, r, true); });
  add_instanced("instance(cone)",
                [](const Placement& p, Rng& r) { return make_cone(p, r, 0.0, true); });
  add_instanced("instance(torus)",
                [](const Placement& p, Rng& r) { return make_torus(p, r, 0.25); });

  const std::vector<Family> sdf_families = {
      Family::kRandom,      Family::kFarMid,      Family::kGrazing,   Family::kTangent,
      Family::kNearTangent, Family::kAxisAligned, Family::kAlongAxis, Family::kOnSurface};
  const auto add_sdf = [&](const std::string& surface, auto make, bool curved_everywhere) {
    for (Family f : sdf_families) {
      if (!curved_everywhere && (f == Family::kTangent || f == Family::kNearTangent)) continue;
      add(surface, family_name(f), ray_row(make, f, Where::kOrigin), 2000);
    }
    add(surface, "offset 1e2-1e6", ray_row(make, Family::kRandom, Where::kOffset), 2000);
    add(surface, "spawn @1e+03", spawn_row(make, 1e3), 1000);
  };
  add_sdf(
      "sdf box", [](const Placement& p, Rng& r) { return make_sdf_box(p, r, 0.0); }, false);
  add_sdf(
      "sdf rounded box", [](const Placement& p, Rng& r) { return make_sdf_box(p, r, 0.3); }, true);
  add_sdf("sdf torus", make_sdf_torus, true);
  add_sdf("sdf capsule", make_sdf_capsule, true);

  for (const bool use_1010 : {false, true}) {
    const std::string solver = use_1010 ? "quartic: Alg. 1010" : "quartic: isolation";
    add(solver, "4 real, separated", quartic_row(QuarticCase::kSeparated, use_1010), 4000);
    add(solver, "2 real + complex pair", quartic_row(QuarticCase::kPairsComplex, use_1010), 4000);
    add(solver, "2 close pairs 1e-6..1e-3", quartic_row(QuarticCase::kClosePairs, use_1010), 4000);
    add(solver, "near-double 1e-9..1e-7", quartic_row(QuarticCase::kNearDouble, use_1010), 4000);
    add(solver, "magnitudes 1e-4..1e4", quartic_row(QuarticCase::kSpread1e4, use_1010), 4000);
    add(solver, "huge root 1e80..1e300", quartic_row(QuarticCase::kHugeRoot, use_1010), 4000);
  }
  add("quartic: isolation", "interval +-1e300", quartic_row(QuarticCase::kHugeInterval, false),
      4000);
  for (double ratio : {0.25, 1e-3, 1e-5}) {
    char name[64];
    std::snprintf(name, sizeof name, "torus/1010 r/R=%g", ratio);
    const auto make = [ratio](const Placement& p, Rng& r) {
      return Torus1010{make_torus(p, r, ratio)};
    };
    for (Family f : {Family::kRandom, Family::kFarExtreme, Family::kGrazing, Family::kTangent,
                     Family::kNearTangent, Family::kAlongAxis, Family::kOnSurface})
      add(name, family_name(f), ray_row(make, f, Where::kOrigin));
  }

  add("mesh: fan 4-1024", "shared edges/vertex", watertight_row(0, 0.0), 20000);
  add("mesh: bipyramid", "shared edges/vertices", watertight_row(1, 0.0), 20000);
  add("mesh: grid", "shared edges/vertices", watertight_row(2, 0.0), 20000);
  add("mesh: bipyramid", "@1e5 shared edges", watertight_row(1, 1e5), 20000);
  add("mesh: fan 4-1024", "@1e5 shared edges", watertight_row(0, 1e5), 20000);
  add("triangle degenerate", "collinear", degenerate_triangle_row(DegenerateKind::kCollinear),
      20000);
  add("triangle degenerate", "coincident vertices",
      degenerate_triangle_row(DegenerateKind::kCoincident), 20000);
  add("triangle degenerate", "sliver h/l=2^-24", degenerate_triangle_row(DegenerateKind::kSliver),
      20000);
  add_patch_rows(rows, bounds_for);
  for (Row& row : later) rows.push_back(std::move(row));
  // Appended last, so every row before keeps its seed (the row's index).
  rows.push_back(Row{"quartic: isolation", "complex pair beside a root", 4000,
                     bounds_for("quartic: isolation", "complex pair beside a root"),
                     quartic_row(QuarticCase::kPairBesideRoot, false)});
  const std::pair<const char*, CubicCase> cubic_cases[] = {
      {"3 real, separated", CubicCase::kSeparated},
      {"1 real + complex pair", CubicCase::kPairComplex},
      {"magnitudes 1e-4..1e4", CubicCase::kSpread1e4},
      {"huge root 1e80..1e300", CubicCase::kHugeRoot},
      {"spread 1e-150..1e150", CubicCase::kSpread}};
  for (const auto& [family, which] : cubic_cases)
    rows.push_back(Row{"cubic", family, 4000, bounds_for("cubic", family), cubic_row(which)});
  return rows;
}

}  // namespace tessera::stress
