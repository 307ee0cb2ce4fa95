#pragma once
// Trimmed faces: a surface with a uv parameterisation bounded by an outer uv loop and any
// number of holes. Intersection takes every hit of the underlying surface (sorted by t)
// and keeps those whose uv lie in the face, so a ray through a hole goes on to the part of
// the surface behind it.
#include <cmath>
#include <cstdint>

#include "tessera/geometry/cone.hpp"
#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/disk.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/spline_patch.hpp"
#include "tessera/geometry/torus.hpp"
#include "tessera/geometry/trim_loops.hpp"

namespace tessera {

template <typename Surface>
struct Trimmed {
  Surface surface;
  TrimRegion region;
};

// The uv each surface reports (surface_at) and which of its directions wrap: u is an angle
// / 2 pi on the sphere, cylinder, cone, disk and torus, and the torus' v is one too.
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Sphere&) {
  return {true, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Cylinder&) {
  return {true, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Cone&) {
  return {true, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Disk&) {
  return {true, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Torus&) {
  return {true, true};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Plane&) {
  return {false, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const Quad&) {
  return {false, false};
}
TESSERA_HD TESSERA_INLINE UvPeriodicity uv_periodicity(const SplinePatch&) {
  return {false, false};
}

// Largest number of hits of one underlying surface (a patch's roots bound them all).
inline constexpr int kMaxFaceHits = kMaxPatchRoots;

namespace detail {

// uv of one hit of the underlying surface, for the trim test. Caps of cylinders and cones
// have a uv of their own (angle, radius) unrelated to the side's: a trimmed face is the
// side only, so cap hits are never in it.
template <typename Surface>
TESSERA_HD bool face_uv(const Surface& surface, const PreciseRay& ray, const HitRecord& hit,
                        dvec2& uv) {
  const SurfaceInteraction si = surface_at(surface, ray, hit);
  uv = dvec2(si.uv);
  return true;
}
TESSERA_HD TESSERA_INLINE bool face_uv(const Cylinder& c, const PreciseRay& ray,
                                       const HitRecord& hit, dvec2& uv) {
  if (static_cast<std::uint32_t>(hit.v) != kPartSide) return false;
  uv = dvec2(surface_at(c, ray, hit).uv);
  return true;
}
TESSERA_HD TESSERA_INLINE bool face_uv(const Cone& c, const PreciseRay& ray, const HitRecord& hit,
                                       dvec2& uv) {
  if (static_cast<std::uint32_t>(hit.v) != kPartSide) return false;
  uv = dvec2(surface_at(c, ray, hit).uv);
  return true;
}
// A patch's hit already holds its parameters.
TESSERA_HD TESSERA_INLINE bool face_uv(const SplinePatch&, const PreciseRay&, const HitRecord& hit,
                                       dvec2& uv) {
  uv = dvec2(hit.u, hit.v);
  return true;
}

template <typename Surface>
TESSERA_HD bool in_face(const Trimmed<Surface>& face, const PreciseRay& ray, const HitRecord& hit) {
  dvec2 uv;
  return face_uv(face.surface, ray, hit, uv) && face_contains(face.region, uv);
}

}  // namespace detail

template <typename Surface>
TESSERA_HD Aabb bounds(const Trimmed<Surface>& face) {
  return bounds(face.surface);
}

// A trimmed plane is finite: its box is that of the outer loop's uv box on the plane.
TESSERA_HD TESSERA_INLINE Aabb bounds(const Trimmed<Plane>& face) {
  const Plane& p = face.surface;
  const AxisFrame frame = AxisFrame::from_axis(p.normal);
  const TrimLoop& outer = face.region.loops[face.region.first_loop];
  dvec3 lower(kInfinity), upper(-kInfinity);
  for (int corner = 0; corner < 4; ++corner) {
    const double u = ((corner & 1) ? outer.upper.x : outer.lower.x) * p.uv_scale;
    const double v = ((corner & 2) ? outer.upper.y : outer.lower.y) * p.uv_scale;
    const dvec3 q = dvec3(p.point) + frame.u * u + frame.v * v;
    lower = glm::min(lower, q);
    upper = glm::max(upper, q);
  }
  return conservative_aabb(lower, upper);
}

template <typename Surface>
TESSERA_HD bool intersect(const Trimmed<Surface>& face, const PreciseRay& ray, float t_max,
                          HitRecord& hit, std::uint32_t primitive) {
  HitRecord hits[kMaxFaceHits];
  const int n = intersect_all(face.surface, ray, t_max, hits, kMaxFaceHits, primitive);
  for (int i = 0; i < n; ++i) {
    if (detail::in_face(face, ray, hits[i])) {
      hit = hits[i];
      return true;
    }
  }
  return false;
}

template <typename Surface>
TESSERA_HD bool intersect(const Trimmed<Surface>& face, const Ray& ray, float t_max, HitRecord& hit,
                          std::uint32_t primitive) {
  return intersect(face, make_precise_ray(ray), t_max, hit, primitive);
}

template <typename Surface>
TESSERA_HD int intersect_all(const Trimmed<Surface>& face, const PreciseRay& ray, float t_max,
                             HitRecord* hits, int max_hits, std::uint32_t primitive) {
  HitRecord candidates[kMaxFaceHits];
  const int n = intersect_all(face.surface, ray, t_max, candidates, kMaxFaceHits, primitive);
  int kept = 0;
  for (int i = 0; i < n && kept < max_hits; ++i)
    if (detail::in_face(face, ray, candidates[i])) hits[kept++] = candidates[i];
  return kept;
}

template <typename Surface>
TESSERA_HD int intersect_all(const Trimmed<Surface>& face, const Ray& ray, float t_max,
                             HitRecord* hits, int max_hits, std::uint32_t primitive) {
  return intersect_all(face, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

template <typename Surface>
TESSERA_HD SurfaceInteraction surface_at(const Trimmed<Surface>& face, const PreciseRay& ray,
                                         const HitRecord& hit) {
  return surface_at(face.surface, ray, hit);
}

template <typename Surface>
TESSERA_HD SurfaceInteraction surface_at(const Trimmed<Surface>& face, const Ray& ray,
                                         const HitRecord& hit) {
  return surface_at(face.surface, make_precise_ray(ray), hit);
}

}  // namespace tessera
