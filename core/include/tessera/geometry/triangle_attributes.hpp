#pragma once
#include <cmath>

#include "tessera/geometry/triangle.hpp"

namespace tessera {

// Per-vertex shading data of a mesh triangle, kept apart from the positions so that
// traversal touches only the 40-byte Triangle. Normals need not be unit (they are
// interpolated, then normalised).
struct TriangleAttributes {
  vec3 n0, n1, n2;
  vec2 uv0, uv1, uv2;
};

// Sets the interpolated shading normal and uv of a triangle hit. The geometric normal stays
// the triangle's own (faced against the ray); the shading normal is flipped into the same
// hemisphere, because interpolated normals can point away from the viewer near
// silhouettes and shading must not see light from behind the surface.
TESSERA_HD TESSERA_INLINE void apply_attributes(SurfaceInteraction& si,
                                                const TriangleAttributes& attributes,
                                                const HitRecord& hit) {
  const float b0 = 1.0f - hit.u - hit.v;
  const vec3 n = b0 * attributes.n0 + hit.u * attributes.n1 + hit.v * attributes.n2;
  const float len2 = glm::dot(n, n);
  if (len2 > 0.0f && std::isfinite(len2)) {
    vec3 shading = n / std::sqrt(len2);
    if (glm::dot(shading, si.geometric_normal) < 0.0f) shading = -shading;
    si.shading_normal = shading;
  }
  si.uv = b0 * attributes.uv0 + hit.u * attributes.uv1 + hit.v * attributes.uv2;
}

// surface_at with interpolated shading normal and uv.
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Triangle& tri,
                                                        const TriangleAttributes& attributes,
                                                        const Ray& ray, const HitRecord& hit) {
  SurfaceInteraction si = surface_at(tri, ray, hit);
  apply_attributes(si, attributes, hit);
  return si;
}

}  // namespace tessera
