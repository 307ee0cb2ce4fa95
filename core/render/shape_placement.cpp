#include "shape_placement.hpp"

namespace tessera {

Plane placed_surface(const PlaneDesc& p, const Placement& at, std::uint32_t material) {
  return Plane::make(at.point(p.point), at.normal(p.normal), material);
}
Disk placed_surface(const DiskDesc& d, const Placement& at, std::uint32_t material) {
  return Disk::make(at.point(d.center), at.direction(d.normal), at.length(d.radius), material,
                    at.length(d.inner_radius));
}
Quad placed_surface(const QuadDesc& q, const Placement& at, std::uint32_t material) {
  // A parallelogram stays one under any affine map.
  return Quad::make(at.point(q.corner), at.vector(q.u), at.vector(q.v), material);
}
Sphere placed_surface(const SphereDesc& s, const Placement& at, std::uint32_t material) {
  return Sphere{at.point(s.center), at.length(s.radius), material};
}
Cylinder placed_surface(const CylinderDesc& c, const Placement& at, std::uint32_t material) {
  return Cylinder::make(at.point(c.base), at.direction(c.axis), at.length(c.radius),
                        at.length(c.height), c.caps, material);
}
Cone placed_surface(const ConeDesc& c, const Placement& at, std::uint32_t material) {
  return Cone::make(at.point(c.base), at.direction(c.axis), at.length(c.base_radius),
                    at.length(c.top_radius), at.length(c.height), c.caps, material);
}
Torus placed_surface(const TorusDesc& t, const Placement& at, std::uint32_t material) {
  return Torus::make(at.point(t.center), at.direction(t.axis), at.length(t.major_radius),
                     at.length(t.minor_radius), material);
}

SdfBox object_space_shape(const SdfBoxDesc& b) {
  return SdfBox{vec3(b.center), vec3(b.half_extent), static_cast<float>(b.rounding), b.material};
}
SdfTorus object_space_shape(const SdfTorusDesc& t) {
  return SdfTorus{vec3(t.center), vec3(glm::normalize(t.axis)), static_cast<float>(t.major_radius),
                  static_cast<float>(t.minor_radius), t.material};
}
SdfCapsule object_space_shape(const SdfCapsuleDesc& c) {
  return SdfCapsule{vec3(c.a), vec3(c.b), static_cast<float>(c.radius), c.material};
}

}  // namespace tessera
