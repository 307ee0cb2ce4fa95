#include "tessera/scene/scene_features.hpp"

#include <string>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

SceneFeatures SceneFeatures::of(const SceneDescription& scene) {
  SceneFeatures f;
  const auto use = [&](unsigned shape, std::uint32_t material) {
    f.shapes |= shape;
    if (material >= scene.materials.size()) return;
    const MaterialDesc& m = scene.materials[material];
    f.material_kinds |= 1u << static_cast<unsigned>(make_material(m).kind);
    if (m.emission.x > 0 || m.emission.y > 0 || m.emission.z > 0) f.light_shapes |= shape;
  };
  for (const auto& s : scene.spheres) use(kShapeSphere, s.material);
  for (const auto& q : scene.quads) use(kShapeQuad, q.material);
  for (const auto& m : scene.meshes)
    if (!m.indices.empty()) use(kShapeTriangle, m.material);
  f.primitive_count = scene.spheres.size() + scene.quads.size() + scene.triangle_count();
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
  if (shapes_text.empty()) shapes_text = "empty";
  return shapes_text + ", " + std::to_string(light_count) + " lights, " +
         std::to_string(primitive_count) + " primitives";
}

}  // namespace tessera
