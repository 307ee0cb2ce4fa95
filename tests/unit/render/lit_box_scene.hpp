#pragma once
// The scene the adaptive-sampling and progressive-refinement tests render.
#include <string>

#include "tessera/scene/scene_description.hpp"

namespace tessera::test {

using glm::dvec3;

// A closed box lit by a small ceiling light: bright, dim and shadowed regions, so the
// pixels need very different sample counts, and an opening to a black background.
inline SceneDescription lit_box(double target_error, std::uint32_t spp) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 3.6};
  scene.camera.fov_degrees = 42.0;
  const auto material = [&](MaterialType type, dvec3 albedo, dvec3 emission = dvec3(0.0)) {
    MaterialDesc m;
    m.name = std::to_string(scene.materials.size());
    m.type = type;
    m.albedo = albedo;
    m.emission = emission;
    scene.materials.push_back(m);
    return static_cast<std::uint32_t>(scene.materials.size() - 1);
  };
  const auto white = material(MaterialType::kLambertian, dvec3(0.7));
  const auto green = material(MaterialType::kLambertian, dvec3(0.2, 0.7, 0.2));
  const auto light = material(MaterialType::kLight, dvec3(1.0), dvec3(25.0));
  const auto quad = [&](dvec3 corner, dvec3 u, dvec3 v, std::uint32_t m) {
    scene.quads.push_back(QuadDesc{.corner = corner, .u = u, .v = v, .material = m});
  };
  quad({-1, -1, -1}, {2, 0, 0}, {0, 0, 2}, white);  // floor
  quad({-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, white);   // ceiling
  quad({-1, -1, -1}, {2, 0, 0}, {0, 2, 0}, white);  // back
  quad({-1, -1, -1}, {0, 2, 0}, {0, 0, 2}, green);  // left
  quad({-0.15, 0.99, -0.15}, {0.3, 0, 0}, {0, 0, 0.3}, light);
  scene.spheres.push_back(
      SphereDesc{.center = {0.3, -0.6, -0.2}, .radius = 0.4, .material = white});
  scene.render.width = 24;
  scene.render.height = 24;
  scene.render.tile_size = 8;
  scene.render.max_depth = 6;
  scene.render.samples_per_pixel = spp;
  scene.render.target_error = target_error;
  scene.render.min_samples_per_pixel = 16;
  scene.render.aovs = kAovVariance | kAovSampleCount;
  return scene;
}

}  // namespace tessera::test
