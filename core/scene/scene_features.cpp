#include "tessera/scene/scene_features.hpp"

#include <string>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

SceneFeatures SceneFeatures::of(const SceneDescription& scene) {
  SceneFeatures f;
  const auto use_material = [&](std::uint32_t index) {
    if (index < scene.materials.size())
      f.material_kinds |= 1u << static_cast<unsigned>(make_material(scene.materials[index]).kind);
  };
  for (const auto& s : scene.spheres) {
    f.shapes |= kShapeSphere;
    use_material(s.material);
  }
  for (const auto& q : scene.quads) {
    f.shapes |= kShapeQuad;
    use_material(q.material);
  }
  for (const auto& m : scene.meshes) {
    if (m.indices.empty()) continue;
    f.shapes |= kShapeTriangle;
    use_material(m.material);
  }
  f.primitive_count = scene.spheres.size() + scene.quads.size() + scene.triangle_count();
  const auto used = [&](BsdfKind kind) {
    return (f.material_kinds & (1u << static_cast<unsigned>(kind))) != 0;
  };
  f.transmissive = used(BsdfKind::kDielectric) || used(BsdfKind::kThinDielectric);
  for (const auto& m : scene.materials)
    if (m.emission.x > 0 || m.emission.y > 0 || m.emission.z > 0) f.emissive = true;
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
