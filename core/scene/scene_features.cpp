#include "tessera/scene/scene_features.hpp"

#include <string>

#include "tessera/render/material_mapping.hpp"

namespace tessera {

SceneFeatures SceneFeatures::of(const SceneDescription& scene) {
  SceneFeatures f;
  const auto use = [&](unsigned shape, std::uint32_t material) {
    f.shapes |= shape;
    if (material >= scene.materials.size()) return;
    const MaterialDesc& m = scene.materials[material];
    f.material_kinds |= 1u << static_cast<unsigned>(make_material(m).kind);
    const glm::dvec3 e = m.emitted_radiance();
    if (e.x > 0 || e.y > 0 || e.z > 0) f.light_shapes |= shape;
  };
  for (const auto& q : scene.quads) use(kShapeQuad, q.material);
  for (const auto& m : scene.meshes)
    if (!m.indices.empty()) use(kShapeTriangle, m.material);
  for (const auto& p : scene.planes) use(kShapePlane, p.material);
  const auto curved = [&](const auto& shapes, unsigned bit) {
    for (const auto& s : shapes)
      use(transform_bakes_into_shape(s.transform) ? bit : kShapeInstance, s.material);
  };
  curved(scene.spheres, kShapeSphere);
  curved(scene.displaced_spheres, kShapeSphere);
  curved(scene.disks, kShapeDisk);
  curved(scene.cylinders, kShapeCylinder);
  curved(scene.cones, kShapeCone);
  curved(scene.tori, kShapeTorus);
  const auto distance_field = [&](const auto& shapes) {
    for (const auto& s : shapes) use(s.transform ? kShapeInstance : kShapeSdf, s.material);
  };
  distance_field(scene.sdf_boxes);
  distance_field(scene.sdf_tori);
  distance_field(scene.sdf_capsules);
  for (const auto& p : scene.patches) use(kShapePatch, p.material);
  for (const auto& t : scene.trimmed_faces) use(kShapeTrimmed, t.material);
  f.primitive_count = scene.analytic_shape_count() + scene.triangle_count();
  const auto used = [&](BsdfKind kind) {
    return (f.material_kinds & (1u << static_cast<unsigned>(kind))) != 0;
  };
  f.transmissive = used(BsdfKind::kDielectric) || used(BsdfKind::kThinDielectric);
  f.emissive = f.light_shapes != 0;
  f.aovs = scene.render.aovs;
  return f;
}

bool SceneFeatures::specular() const {
  constexpr std::uint32_t kSpecularKinds =
      (1u << static_cast<unsigned>(BsdfKind::kConductor)) |
      (1u << static_cast<unsigned>(BsdfKind::kDielectric)) |
      (1u << static_cast<unsigned>(BsdfKind::kThinDielectric)) |
      (1u << static_cast<unsigned>(BsdfKind::kCoated));
  return (material_kinds & kSpecularKinds) != 0;
}

std::string SceneFeatures::summary() const {
  std::string shapes_text;
  const auto add = [&](unsigned bit, const char* name) {
    if ((shapes & bit) == 0) return;
    if (!shapes_text.empty()) shapes_text += "+";
    shapes_text += name;
  };
  add(kShapeSphere, "spheres");
  add(kShapeQuad, "quads");
  add(kShapeTriangle, "triangles");
  add(kShapePlane, "planes");
  add(kShapeDisk, "disks");
  add(kShapeCylinder, "cylinders");
  add(kShapeCone, "cones");
  add(kShapeTorus, "tori");
  add(kShapeSdf, "sdfs");
  add(kShapeInstance, "instances");
  add(kShapePatch, "patches");
  add(kShapeTrimmed, "trimmed faces");
  if (shapes_text.empty()) shapes_text = "empty";
  return shapes_text + ", " + std::to_string(light_count) + " lights, " +
         std::to_string(primitive_count) + " primitives";
}

}  // namespace tessera
