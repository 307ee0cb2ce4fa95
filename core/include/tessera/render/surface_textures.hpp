#pragma once
// What a material's textures and patterns make of it at one hit: the albedo there, the
// roughness there, and the uv footprint that picks a texture's mip level.
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "tessera/render/golf_dimples.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/render/texture.hpp"

namespace tessera {

// uv units per unit of surface length at a hit: the square root of the uv area one unit of
// surface area maps to. Known for triangles, spheres, rectangles and planes; 0 elsewhere,
// which makes a lookup read the finest mip level (the pixel's samples filter it then).
TESSERA_HD inline float uv_per_length(const SceneView& scene, std::uint32_t primitive,
                                      const vec2& uv) {
  const std::uint32_t i = primitive_index(primitive);
  switch (primitive_type(primitive)) {
    case PrimitiveType::kTriangle: {
      const Triangle& t = scene.triangles[i];
      // Without stored uvs a triangle's uv are its barycentrics.
      vec2 d1(1.0f, 0.0f), d2(0.0f, 1.0f);
      if (scene.triangle_attributes != nullptr) {
        const TriangleAttributes& a = scene.triangle_attributes[i];
        d1 = a.uv1 - a.uv0;
        d2 = a.uv2 - a.uv0;
      }
      const float uv_area = std::fabs(d1.x * d2.y - d1.y * d2.x);
      const float area = glm::length(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
      return area > 0.0f ? std::sqrt(uv_area / area) : 0.0f;
    }
    case PrimitiveType::kSphere: {
      // u = phi / 2 pi, v = theta / pi: du dv = dA / (2 pi^2 r^2 sin theta).
      const float sin_theta = std::fmax(std::sin(kPi * uv.y), 1e-3f);
      return 1.0f / (kPi * scene.spheres[i].radius * std::sqrt(2.0f * sin_theta));
    }
    case PrimitiveType::kQuad:
      return std::sqrt(glm::length(scene.quads[i].w));  // |w| = 1 / |u x v|
    case PrimitiveType::kPlane:
      return 1.0f / scene.planes[i].uv_scale;
    default:
      return 0.0f;
  }
}

// A texture lookup at a hit: `footprint` is the width of surface the lookup stands for
// (the ray cone's width there, world units; 0: the finest level).
TESSERA_HD inline vec3 texture_at(const SceneView& scene, std::int32_t texture,
                                  std::uint32_t primitive, const vec2& uv, float footprint) {
  const float uv_footprint =
      footprint > 0.0f ? footprint * uv_per_length(scene, primitive, uv) : 0.0f;
  return evaluate_texture(scene.textures[texture], scene.texels, uv, uv_footprint);
}

// The albedo of `material` at a hit: its texture's, or its pattern's, where it has one.
// RayON measures the pattern from a sphere's centre and from the world origin on every other
// shape; an instanced sphere uses its object-space centre.
TESSERA_HD inline vec3 albedo_at(const SceneView& scene, const Material& material,
                                 std::uint32_t primitive, const SurfaceInteraction& si,
                                 float footprint = 0.0f) {
  if (material.albedo_texture >= 0)
    return texture_at(scene, material.albedo_texture, primitive, si.uv, footprint);
  if (material.pattern.type == PatternType::kNone) return material.albedo;
  vec3 from_centre = si.position;
  const std::uint32_t i = primitive_index(primitive);
  switch (primitive_type(primitive)) {
    case PrimitiveType::kSphere:
      from_centre = si.position - scene.spheres[i].center;
      break;
    case PrimitiveType::kSphereInstance: {
      const Instance<Sphere>& instance = scene.sphere_instances[i];
      from_centre =
          vec3(instance.world_to_object.point(dvec3(si.position))) - instance.shape.center;
      break;
    }
    default:
      break;
  }
  return patterned_albedo(material.pattern, material.albedo, from_centre);
}

// Room for a textured copy of a material that is not filled unless a texture needs it: a
// Material has defaults for its twenty fields, and constructing one at every path vertex
// only to leave it unused cost 0.9% of the colour-bleed box's render instructions. The union leaves the member unconstructed;
// material_at's assignment (trivial) starts its lifetime.
struct MaterialScratch {
  union {
    Material material;
  };
  TESSERA_HD MaterialScratch() {}
};
static_assert(std::is_trivially_copy_assignable_v<Material> &&
              std::is_trivially_destructible_v<Material>);

// `material` with its roughness texture applied at the hit: `scratch` receives the copy
// when there is one (no copy otherwise).
TESSERA_HD inline const Material& material_at(const SceneView& scene, const Material& material,
                                              std::uint32_t primitive, const SurfaceInteraction& si,
                                              float footprint, MaterialScratch& scratch) {
  if (material.roughness_texture < 0) return material;
  scratch.material = material;
  scratch.material.set_roughness(
      texture_scalar(texture_at(scene, material.roughness_texture, primitive, si.uv, footprint)));
  return scratch.material;
}

// Tilts `si`'s shading normal by the golf-ball dimples of a displaced sphere's material
// (nothing for other materials). The dimples are laid out in the sphere's own frame, so they
// turn with an instanced sphere.
TESSERA_HD inline void apply_golf_dimples(const SceneView& scene, const Material& material,
                                          std::uint32_t primitive, const Ray& ray,
                                          SurfaceInteraction& si) {
  if (!(material.golf_dimples > 0.0f)) return;
  const std::uint32_t i = primitive_index(primitive);
  vec3 outward = si.front_face ? si.geometric_normal : -si.geometric_normal;
  const vec3 to_eye = -glm::normalize(ray.direction);
  if (primitive_type(primitive) == PrimitiveType::kSphereInstance) {
    // Into the object's frame and back (the inverse transpose carries normals).
    const Instance<Sphere>& instance = scene.sphere_instances[i];
    const vec3 local = glm::normalize(vec3(instance.world_to_object.vector(dvec3(outward))));
    const vec3 local_eye = glm::normalize(vec3(instance.world_to_object.vector(dvec3(to_eye))));
    const vec3 n = golf_dimpled_normal(local, local_eye, material.golf_dimples);
    outward = glm::normalize(vec3(glm::transpose(instance.world_to_object.linear) * dvec3(n)));
  } else {
    outward = golf_dimpled_normal(outward, to_eye, material.golf_dimples);
  }
  si.shading_normal = si.front_face ? outward : -outward;
}

}  // namespace tessera
