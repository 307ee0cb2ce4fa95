#include "light_list.hpp"

#include <algorithm>

namespace tessera {

void add_if_sampled_emitter(std::vector<LightSource>& lights, const Material& material,
                            std::uint32_t primitive, float sampled_area, bool visible) {
  if (material.emissive() && sampled_area > 0.0f)
    lights.push_back(LightSource{primitive, sampled_area, 0.0f, visible});
}

namespace {

std::uint32_t light_material(const SceneView& shapes, std::uint32_t primitive) {
  const std::uint32_t index = primitive_index(primitive);
  switch (primitive_type(primitive)) {
    case PrimitiveType::kSphere:
      return shapes.spheres[index].material;
    case PrimitiveType::kQuad:
      return shapes.quads[index].material;
    case PrimitiveType::kTriangle:
      return shapes.triangles[index].material;
    case PrimitiveType::kDisk:
      return shapes.disks[index].material;
    default:
      return 0;
  }
}

}  // namespace

std::vector<AliasSlot> finish_light_list(std::vector<LightSource>& lights,
                                         std::span<const Material> materials,
                                         const SceneView& shapes) {
  std::sort(lights.begin(), lights.end(),
            [](const LightSource& a, const LightSource& b) { return a.primitive < b.primitive; });
  std::vector<double> power(lights.size());
  double total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const vec3 e = materials[light_material(shapes, lights[i].primitive)].emission;
    const double luminance = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
    // An emitter whose luminance is zero (pure colours cannot be) still lights the scene.
    power[i] = std::max(luminance, 1e-3 * std::max({e.x, e.y, e.z})) * lights[i].area;
    total += power[i];
  }
  for (std::size_t i = 0; i < lights.size(); ++i)
    lights[i].pmf = total > 0.0 ? static_cast<float>(power[i] / total)
                                : 1.0f / static_cast<float>(lights.size());
  return build_alias_table(power);
}

}  // namespace tessera
