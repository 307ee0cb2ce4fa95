#pragma once
// Random shapes and surface points for the stress families, all in double; rays are
// rounded to float only at the end, and the references then use the float values exactly.
#include <algorithm>
#include <cmath>
#include <random>

#include "tessera/geometry/cone.hpp"
#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/disk.hpp"
#include "tessera/geometry/instance.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/sphere_tracing.hpp"
#include "tessera/geometry/torus.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera::stress {

constexpr double kTwoPi = 6.283185307179586476925;

struct Rng {
  std::mt19937_64 engine;
  explicit Rng(std::uint64_t seed) : engine(seed) {}
  double uniform(double a = 0.0, double b = 1.0) {
    return std::uniform_real_distribution<double>(a, b)(engine);
  }
  double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  bool coin(double p = 0.5) { return uniform() < p; }
  dvec3 unit_vector() {
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, kTwoPi);
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return dvec3(s * std::cos(phi), s * std::sin(phi), z);
  }
  dvec3 in_ball(double radius) { return unit_vector() * (radius * std::cbrt(uniform())); }
  dvec3 perpendicular_unit(const dvec3& n) {
    for (;;) {
      const dvec3 v = unit_vector();
      const dvec3 p = v - glm::dot(v, n) * n;
      const double l = glm::length(p);
      if (l > 1e-3) return p / l;
    }
  }
};

struct SurfacePoint {
  dvec3 point;
  dvec3 normal;  // unit, outward
};

struct BoundingSphere {
  dvec3 center;
  double radius;
};

// ---- sphere
inline BoundingSphere bounding_sphere(const Sphere& s) {
  return {dvec3(s.center), s.radius};
}
inline SurfacePoint sample_surface(const Sphere& s, Rng& rng) {
  const dvec3 n = rng.unit_vector();
  return {dvec3(s.center) + static_cast<double>(s.radius) * n, n};
}
inline dvec3 shape_axis(const Sphere&, Rng& rng) {
  return rng.unit_vector();
}

// ---- plane: sampled within uv_scale of its point (the stress setups set uv_scale to the
// scale of the case, which only changes texture coordinates)
inline BoundingSphere bounding_sphere(const Plane& p) {
  return {dvec3(p.point), p.uv_scale};
}
inline SurfacePoint sample_surface(const Plane& p, Rng& rng) {
  const dvec3 n = glm::normalize(dvec3(p.normal));
  return {dvec3(p.point) + rng.perpendicular_unit(n) * (p.uv_scale * std::sqrt(rng.uniform())), n};
}
inline dvec3 shape_axis(const Plane& p, Rng&) {
  return glm::normalize(dvec3(p.normal));
}

// ---- disk
inline BoundingSphere bounding_sphere(const Disk& d) {
  return {dvec3(d.center), d.radius};
}
inline SurfacePoint sample_surface(const Disk& d, Rng& rng) {
  const dvec3 n = glm::normalize(dvec3(d.normal));
  const double ri = d.inner_radius, r = d.radius;
  const double rho = std::sqrt(rng.uniform(ri * ri, r * r));
  return {dvec3(d.center) + rng.perpendicular_unit(n) * rho, n};
}
inline dvec3 shape_axis(const Disk& d, Rng&) {
  return glm::normalize(dvec3(d.normal));
}

// ---- quad
inline BoundingSphere bounding_sphere(const Quad& q) {
  const dvec3 c = dvec3(q.corner) + 0.5 * dvec3(q.u) + 0.5 * dvec3(q.v);
  return {c, 0.5 * std::max(glm::length(dvec3(q.u) + dvec3(q.v)),
                            glm::length(dvec3(q.u) - dvec3(q.v)))};
}
inline SurfacePoint sample_surface(const Quad& q, Rng& rng) {
  const dvec3 n = glm::normalize(glm::cross(dvec3(q.u), dvec3(q.v)));
  return {dvec3(q.corner) + rng.uniform() * dvec3(q.u) + rng.uniform() * dvec3(q.v), n};
}
inline dvec3 shape_axis(const Quad& q, Rng&) {
  return glm::normalize(glm::cross(dvec3(q.u), dvec3(q.v)));
}

// ---- triangle
inline BoundingSphere bounding_sphere(const Triangle& t) {
  const dvec3 c = (dvec3(t.p0) + dvec3(t.p1) + dvec3(t.p2)) / 3.0;
  const double r = std::max(
      {glm::length(dvec3(t.p0) - c), glm::length(dvec3(t.p1) - c), glm::length(dvec3(t.p2) - c)});
  return {c, r};
}
inline SurfacePoint sample_surface(const Triangle& t, Rng& rng) {
  double a = rng.uniform(), b = rng.uniform();
  if (a + b > 1.0) {
    a = 1.0 - a;
    b = 1.0 - b;
  }
  const dvec3 p0(t.p0), p1(t.p1), p2(t.p2);
  return {p0 + a * (p1 - p0) + b * (p2 - p0), glm::normalize(glm::cross(p1 - p0, p2 - p0))};
}
inline dvec3 shape_axis(const Triangle& t, Rng&) {
  return glm::normalize(glm::cross(dvec3(t.p1) - dvec3(t.p0), dvec3(t.p2) - dvec3(t.p0)));
}

// ---- cylinder and cone: lateral points (and caps by area when capped)
inline SurfacePoint sample_lateral(const dvec3& base, const dvec3& axis, double r0, double r1,
                                   double h, bool capped, Rng& rng) {
  const AxisFrame f = AxisFrame::from_axis(vec3(axis));
  const double slope = (r1 - r0) / h;
  const double side_area = kTwoPi * 0.5 * (r0 + r1) * std::sqrt((r1 - r0) * (r1 - r0) + h * h);
  const double cap_area = capped ? 0.5 * kTwoPi * (r0 * r0 + r1 * r1) : 0.0;
  const double phi = rng.uniform(0.0, kTwoPi);
  const dvec3 radial = f.u * std::cos(phi) + f.v * std::sin(phi);
  if (rng.uniform() * (side_area + cap_area) < side_area) {
    const double z = rng.uniform(0.0, h);
    const double radius = r0 + slope * z;
    return {base + f.w * z + radial * radius, glm::normalize(radial - slope * f.w)};
  }
  const bool bottom = rng.uniform() * (r0 * r0 + r1 * r1) < r0 * r0;
  const double radius = (bottom ? r0 : r1) * std::sqrt(rng.uniform());
  return {base + f.w * (bottom ? 0.0 : h) + radial * radius, bottom ? -f.w : f.w};
}
inline BoundingSphere bounding_sphere(const Cylinder& c) {
  const dvec3 w = glm::normalize(dvec3(c.axis));
  return {dvec3(c.base) + 0.5 * c.height * w,
          std::hypot(static_cast<double>(c.radius), 0.5 * c.height)};
}
inline SurfacePoint sample_surface(const Cylinder& c, Rng& rng) {
  return sample_lateral(dvec3(c.base), glm::normalize(dvec3(c.axis)), c.radius, c.radius, c.height,
                        c.capped != 0, rng);
}
inline dvec3 shape_axis(const Cylinder& c, Rng&) {
  return glm::normalize(dvec3(c.axis));
}

inline BoundingSphere bounding_sphere(const Cone& c) {
  const dvec3 w = glm::normalize(dvec3(c.axis));
  return {dvec3(c.base) + 0.5 * c.height * w,
          std::hypot(static_cast<double>(std::max(c.base_radius, c.top_radius)), 0.5 * c.height)};
}
inline SurfacePoint sample_surface(const Cone& c, Rng& rng) {
  return sample_lateral(dvec3(c.base), glm::normalize(dvec3(c.axis)), c.base_radius, c.top_radius,
                        c.height, c.capped != 0, rng);
}
inline dvec3 shape_axis(const Cone& c, Rng&) {
  return glm::normalize(dvec3(c.axis));
}

// ---- torus: uniform in both angles over the visible surface
inline BoundingSphere bounding_sphere(const Torus& t) {
  return {dvec3(t.center), static_cast<double>(t.major_radius) + t.minor_radius};
}
inline SurfacePoint sample_surface(const Torus& t, Rng& rng) {
  const AxisFrame f = AxisFrame::from_axis(t.axis);
  const double R = t.major_radius, r = t.minor_radius;
  const double theta_max = r > R ? std::acos(-R / r) : kTwoPi / 2.0;
  const double theta = rng.uniform(-theta_max, theta_max);
  const double phi = rng.uniform(0.0, kTwoPi);
  const dvec3 radial = f.u * std::cos(phi) + f.v * std::sin(phi);
  const dvec3 normal = radial * std::cos(theta) + f.w * std::sin(theta);
  return {dvec3(t.center) + radial * R + normal * r, normal};
}
inline dvec3 shape_axis(const Torus& t, Rng&) {
  return glm::normalize(dvec3(t.axis));
}

// ---- instances: the object's samples mapped to world
template <typename Shape>
BoundingSphere bounding_sphere(const Instance<Shape>& instance) {
  const Aabb box = bounds(instance);
  const dvec3 lo(box.lower), hi(box.upper);
  return {0.5 * (lo + hi), 0.5 * glm::length(hi - lo)};
}
template <typename Shape>
SurfacePoint sample_surface(const Instance<Shape>& instance, Rng& rng) {
  const SurfacePoint s = sample_surface(instance.shape, rng);
  const dvec3 n = glm::transpose(instance.world_to_object.linear) * s.normal;
  return {instance.object_to_world.point(s.point), glm::normalize(n)};
}
template <typename Shape>
dvec3 shape_axis(const Instance<Shape>& instance, Rng& rng) {
  return glm::normalize(instance.object_to_world.vector(shape_axis(instance.shape, rng)));
}

}  // namespace tessera::stress

namespace tessera::stress {

// ---- lower bounds on the distance from p to each surface (used to keep the origins of
// the non-"origin on surface" families off the surface: an origin within about an ulp of
// a surface is, by the intersectors' rule, a ray starting on it)

inline double surface_distance_bound(const Sphere& s, const dvec3& p) {
  return std::fabs(glm::length(p - dvec3(s.center)) - s.radius);
}
inline double plane_distance(const dvec3& p, const dvec3& point, const dvec3& normal) {
  return std::fabs(glm::dot(p - point, glm::normalize(normal)));
}
inline double surface_distance_bound(const Plane& s, const dvec3& p) {
  return plane_distance(p, dvec3(s.point), dvec3(s.normal));
}
inline double surface_distance_bound(const Disk& s, const dvec3& p) {
  return plane_distance(p, dvec3(s.center), dvec3(s.normal));
}
inline double surface_distance_bound(const Quad& s, const dvec3& p) {
  return plane_distance(p, dvec3(s.corner), glm::cross(dvec3(s.u), dvec3(s.v)));
}
inline double surface_distance_bound(const Triangle& s, const dvec3& p) {
  return plane_distance(p, dvec3(s.p0),
                        glm::cross(dvec3(s.p1) - dvec3(s.p0), dvec3(s.p2) - dvec3(s.p0)));
}
inline double lateral_distance_bound(const dvec3& p, const dvec3& base, const dvec3& axis,
                                     double r0, double r1, double h) {
  const dvec3 w = glm::normalize(axis);
  const dvec3 q = p - base;
  const double z = glm::dot(q, w);
  const double rho = glm::length(q - z * w);
  const double k = (r1 - r0) / h;
  return std::min(
      {std::fabs(rho - (r0 + k * z)) / std::sqrt(1.0 + k * k), std::fabs(z), std::fabs(z - h)});
}
inline double surface_distance_bound(const Cylinder& s, const dvec3& p) {
  return lateral_distance_bound(p, dvec3(s.base), dvec3(s.axis), s.radius, s.radius, s.height);
}
inline double surface_distance_bound(const Cone& s, const dvec3& p) {
  return lateral_distance_bound(p, dvec3(s.base), dvec3(s.axis), s.base_radius, s.top_radius,
                                s.height);
}
inline double surface_distance_bound(const Torus& s, const dvec3& p) {
  const dvec3 w = glm::normalize(dvec3(s.axis));
  const dvec3 q = p - dvec3(s.center);
  const double z = glm::dot(q, w);
  const double rho = glm::length(q - z * w);
  const double R = s.major_radius, r = s.minor_radius;
  return std::min(std::fabs(std::hypot(rho - R, z) - r), std::fabs(std::hypot(rho + R, z) - r));
}

// ---- signed-distance primitives: points found by projecting random points along the
// gradient of the exact distance (one step lands on the surface)
template <typename Sdf>
dvec3 sdf_gradient_unit(const Sdf& shape, const dvec3& local) {
  const double h = 1e-7 * (1.0 + glm::length(local));
  const dvec3 g(signed_distance(shape, local + dvec3(h, 0, 0)) -
                    signed_distance(shape, local - dvec3(h, 0, 0)),
                signed_distance(shape, local + dvec3(0, h, 0)) -
                    signed_distance(shape, local - dvec3(0, h, 0)),
                signed_distance(shape, local + dvec3(0, 0, h)) -
                    signed_distance(shape, local - dvec3(0, 0, h)));
  return glm::normalize(g);
}
template <typename Sdf>
BoundingSphere sdf_bounding_sphere(const Sdf& shape) {
  dvec3 lower, upper;
  sdf_local_bounds(shape, lower, upper);
  return {sdf_reference_point(shape) + 0.5 * (lower + upper), 0.5 * glm::length(upper - lower)};
}
template <typename Sdf>
SurfacePoint sdf_sample_surface(const Sdf& shape, Rng& rng) {
  const BoundingSphere b = sdf_bounding_sphere(shape);
  const dvec3 origin = sdf_reference_point(shape);
  for (;;) {
    dvec3 p = b.center + rng.in_ball(b.radius) - origin;
    for (int i = 0; i < 4; ++i) p -= signed_distance(shape, p) * sdf_gradient_unit(shape, p);
    if (std::fabs(signed_distance(shape, p)) < 1e-12 * b.radius)
      return {p + origin, sdf_gradient_unit(shape, p)};
  }
}
inline BoundingSphere bounding_sphere(const SdfBox& s) {
  return sdf_bounding_sphere(s);
}
inline BoundingSphere bounding_sphere(const SdfTorus& s) {
  return sdf_bounding_sphere(s);
}
inline BoundingSphere bounding_sphere(const SdfCapsule& s) {
  return sdf_bounding_sphere(s);
}
inline SurfacePoint sample_surface(const SdfBox& s, Rng& rng) {
  return sdf_sample_surface(s, rng);
}
inline SurfacePoint sample_surface(const SdfTorus& s, Rng& rng) {
  return sdf_sample_surface(s, rng);
}
inline SurfacePoint sample_surface(const SdfCapsule& s, Rng& rng) {
  return sdf_sample_surface(s, rng);
}
inline dvec3 shape_axis(const SdfBox&, Rng& rng) {
  dvec3 e(0.0);
  e[static_cast<int>(rng.uniform(0.0, 3.0)) % 3] = 1.0;
  return e;
}
inline dvec3 shape_axis(const SdfTorus& s, Rng&) {
  return glm::normalize(dvec3(s.axis));
}
inline dvec3 shape_axis(const SdfCapsule& s, Rng&) {
  return glm::normalize(dvec3(s.b) - dvec3(s.a));
}
inline double surface_distance_bound(const SdfBox& s, const dvec3& p) {
  return std::fabs(signed_distance(s, p - dvec3(s.center)));
}
inline double surface_distance_bound(const SdfTorus& s, const dvec3& p) {
  return std::fabs(signed_distance(s, p - dvec3(s.center)));
}
inline double surface_distance_bound(const SdfCapsule& s, const dvec3& p) {
  return std::fabs(signed_distance(s, p - dvec3(s.a)));
}
// Flat faces of a box have no tangent line outside their own plane (the tangent families
// are run on the rounded box only, whose edges and corners are curved).
inline bool on_flat_part(const SdfBox&, const SurfacePoint& p) {
  const dvec3 n = glm::abs(p.normal);
  return glm::max(n.x, glm::max(n.y, n.z)) > 0.999;
}
inline double feature_size(const SdfTorus& t) {
  return t.minor_radius;
}

// Whether an origin is so close to the surface that the intersector would treat the ray as
// starting on it (4x the band of make_precise_ray, with the instance's stretch).
template <typename Shape>
bool origin_on_surface(const Shape& shape, const dvec3& origin) {
  return surface_distance_bound(shape, origin) <= 4.0 * std::ldexp(max_abs(origin), -23);
}
template <typename Shape>
bool origin_on_surface(const Instance<Shape>& instance, const dvec3& origin) {
  const glm::dmat3& m = instance.world_to_object.linear;
  const double norm = std::sqrt(glm::dot(m[0], m[0]) + glm::dot(m[1], m[1]) + glm::dot(m[2], m[2]));
  const dvec3 object = instance.world_to_object.point(origin);
  return surface_distance_bound(instance.shape, object) <=
         4.0 * norm * std::ldexp(max_abs(origin), -23);
}

// Smallest feature of a shape: rays starting on it ignore reference roots closer than
// 1e-3 of this (the spurious roots are ~1e-7 relative; a thin torus's far wall is at
// 2r, not at the size of the torus).
inline double feature_size(const Torus& t) {
  return std::min(t.minor_radius, t.major_radius + t.minor_radius);
}
inline double feature_size(const Cylinder& c) {
  return std::min(c.radius, c.height);
}
template <typename Shape>
double feature_size(const Shape& shape) {
  return bounding_sphere(shape).radius;
}
template <typename Shape>
double feature_size(const Instance<Shape>& instance) {
  const glm::dmat3& m = instance.object_to_world.linear;
  double smallest = glm::length(m[0]);
  for (int c = 1; c < 3; ++c) smallest = std::min(smallest, glm::length(m[c]));
  return feature_size(instance.shape) * std::min(1.0, smallest);
}

// Points on flat parts (caps) have no tangent line that is not in the part's own plane.
template <typename Shape>
bool on_flat_part(const Shape&, const SurfacePoint&) {
  return false;
}
inline bool on_flat_part(const Cylinder& c, const SurfacePoint& s) {
  return std::fabs(glm::dot(s.normal, glm::normalize(dvec3(c.axis)))) > 0.999;
}
inline bool on_flat_part(const Cone& c, const SurfacePoint& s) {
  return std::fabs(glm::dot(s.normal, glm::normalize(dvec3(c.axis)))) > 0.999;
}
template <typename Shape>
bool on_flat_part(const Instance<Shape>& instance, const SurfacePoint& s) {
  const dvec3 object_normal =
      glm::normalize(glm::transpose(instance.object_to_world.linear) * s.normal);
  return on_flat_part(instance.shape,
                      SurfacePoint{instance.world_to_object.point(s.point), object_normal});
}

}  // namespace tessera::stress

namespace tessera::stress {

// Distance of `point` from the surface in units of the band within which the intersectors
// treat a ray from `origin` as starting on the surface (make_precise_ray, instance stretch).
template <typename Shape>
double band_ratio(const Shape& shape, const dvec3& origin, const dvec3& point) {
  return surface_distance_bound(shape, point) / std::ldexp(max_abs(origin), -23);
}
template <typename Shape>
double band_ratio(const Instance<Shape>& instance, const dvec3& origin, const dvec3& point) {
  const glm::dmat3& m = instance.world_to_object.linear;
  const double norm = std::sqrt(glm::dot(m[0], m[0]) + glm::dot(m[1], m[1]) + glm::dot(m[2], m[2]));
  return surface_distance_bound(instance.shape, instance.world_to_object.point(point)) /
         (norm * std::ldexp(max_abs(origin), -23));
}

}  // namespace tessera::stress
