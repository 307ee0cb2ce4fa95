#pragma once
// Placement of analytic shapes: a geometry entry's transform is baked into the shape where
// the shape type can represent the result, and the shape becomes an Instance<Shape> where
// it cannot (scene_data.hpp explains the split of primitive types).
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include "primitive_list.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {

// A geometry entry's transform, in the forms baking and instancing need.
struct Placement {
  AffineTransform affine;  // identity when the entry has none
  double scale = 1.0;      // |uniform scale|, for lengths of baked shapes

  explicit Placement(const std::optional<TransformDesc>& transform) {
    if (!transform) return;
    const glm::dmat4 m = transform->matrix();
    affine.linear = glm::dmat3(m);
    affine.translation = glm::dvec3(m[3]);
    scale = std::fabs(transform->scale.x);
  }
  vec3 point(const glm::dvec3& p) const { return vec3(affine.point(p)); }
  vec3 vector(const glm::dvec3& v) const { return vec3(affine.vector(v)); }
  // A direction: unit, mapped by the linear part (axes of shapes under a similarity).
  vec3 direction(const glm::dvec3& v) const { return vec3(glm::normalize(affine.vector(v))); }
  // A surface normal: by the inverse transpose, so it stays perpendicular under any map.
  vec3 normal(const glm::dvec3& n) const {
    return vec3(glm::normalize(glm::transpose(glm::inverse(affine.linear)) * n));
  }
  float length(double l) const { return static_cast<float>(l * scale); }
};

// The identity placement: a surface in its own space (for instances and trimmed faces).
inline const Placement kObjectSpace{std::nullopt};

// The instance of `shape` placed by `transform` (validated non-singular before this runs).
template <typename Shape>
Instance<Shape> make_instance(const Shape& shape, const std::optional<TransformDesc>& transform) {
  Instance<Shape> instance;
  if (!Instance<Shape>::make(shape, Placement(transform).affine, instance))
    throw std::invalid_argument("singular geometry transform (validate_scene rejects these)");
  return instance;
}

// Each surface type built from its description where `at` puts it: kObjectSpace gives the
// surface in its own space; a similarity gives the baked world shape (lengths scale by |s|,
// axes rotate, normals by the inverse transpose). `material` is the entry's own, or the
// face's for a trimmed surface.
Plane placed_surface(const PlaneDesc& p, const Placement& at, std::uint32_t material);
Disk placed_surface(const DiskDesc& d, const Placement& at, std::uint32_t material);
Quad placed_surface(const QuadDesc& q, const Placement& at, std::uint32_t material);
Sphere placed_surface(const SphereDesc& s, const Placement& at, std::uint32_t material);
Cylinder placed_surface(const CylinderDesc& c, const Placement& at, std::uint32_t material);
Cone placed_surface(const ConeDesc& c, const Placement& at, std::uint32_t material);
Torus placed_surface(const TorusDesc& t, const Placement& at, std::uint32_t material);

// A signed-distance shape in its own space (its transform, if any, makes it an instance).
SdfBox object_space_shape(const SdfBoxDesc& b);
SdfTorus object_space_shape(const SdfTorusDesc& t);
SdfCapsule object_space_shape(const SdfCapsuleDesc& c);

// A curved shape, baked into `baked` when its transform is a similarity (it stays the same
// shape type), instanced into `instances` otherwise (non-uniform scale).
template <typename Desc, typename Shape>
void place_curved(const Desc& desc, std::vector<Shape>& baked, PrimitiveType baked_type,
                  std::vector<Instance<Shape>>& instances, PrimitiveType instance_type,
                  PrimitiveList& primitives) {
  if (transform_bakes_into_shape(desc.transform))
    primitives.store(baked, baked_type,
                     placed_surface(desc, Placement(desc.transform), desc.material), desc.visible,
                     desc.material);
  else
    primitives.store(
        instances, instance_type,
        make_instance(placed_surface(desc, kObjectSpace, desc.material), desc.transform),
        desc.visible, desc.material);
}

// A signed-distance shape: its box is axis-aligned in its own space, so a rotation needs an
// instance anyway; every transformed one is instanced to keep one rule.
template <typename Desc, typename Shape>
void place_sdf(const Desc& desc, std::vector<Shape>& plain, PrimitiveType plain_type,
               std::vector<Instance<Shape>>& instances, PrimitiveType instance_type,
               PrimitiveList& primitives) {
  const Shape shape = object_space_shape(desc);
  if (!desc.transform)
    primitives.store(plain, plain_type, shape, desc.visible, desc.material);
  else
    primitives.store(instances, instance_type, make_instance(shape, desc.transform), desc.visible,
                     desc.material);
}

}  // namespace tessera
