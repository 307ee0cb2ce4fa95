#pragma once
// The scenes the device path is checked on, shared by the CPU's device-layout tests
// (unit_render) and the GPU's image tests (unit_gpu), so both cover the same shapes, lights
// and materials: the examples, the converge suite's scenes that need no generated files
// (between them every light kind, every shape the device walks but patches and trimmed
// faces, the conductors, mirrors, glass and image textures) and the materials none of those
// files uses. Each is shrunk to 40 x 30 pixels at 4 spp, so a test renders all of them in
// seconds.
#include <filesystem>
#include <string>
#include <vector>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera::device_tests {

struct DeviceTestScene {
  std::string name;
  SceneDescription scene;
};

inline void shrink_for_device_tests(RenderSettings& r) {
  r.width = 40;
  r.height = 30;
  r.samples_per_pixel = 4;
  r.max_depth = 5;
  r.tile_size = 16;
}

inline std::vector<DeviceTestScene> device_test_scenes() {
  const std::filesystem::path source(TESSERA_SOURCE_DIR);
  const std::filesystem::path examples = source / "examples" / "scenes";
  const std::filesystem::path converge = source / "bench" / "converge" / "scenes";
  std::vector<DeviceTestScene> scenes;
  const auto add = [&](std::string name, LoadedScene loaded) {
    shrink_for_device_tests(loaded.scene.render);
    scenes.push_back({std::move(name), std::move(loaded.scene)});
  };
  for (const char* name : {"cornell.yaml", "shapes.yaml", "textures.yaml"})
    add(name, load_scene_file(examples / name));
  for (const char* name :
       {"daylight_room.yaml", "glossy_glass.yaml", "heldout_corridor.yaml",
        "heldout_instances.yaml", "heldout_lampshade.yaml", "heldout_night_street.yaml",
        "heldout_stage.yaml", "lights_and_sky.yaml", "many_lights.yaml", "rough_materials.yaml",
        "textured.yaml", "two_lights.yaml"})
    add(name, load_scene_file(converge / name));
  add("film, coat and unlit materials", load_scene_yaml(R"(
camera: { position: [0, 1, 4], look_at: [0, 0.5, 0], fov: 40 }
materials:
  - { name: floor, type: lambertian, albedo: [0.7, 0.7, 0.7] }
  - { name: lamp, type: light, emission: [6, 6, 6] }
  - { name: bubble, type: thin_film, film_thickness: 420, film_ior: 1.33 }
  - { name: coat, type: clear_coat, albedo: [0.6, 0.1, 0.1], roughness: 0.2 }
  - { name: flat, type: constant, albedo: [0.2, 0.8, 0.2] }
  - { name: normals, type: show_normals }
geometry:
  - { type: rectangle, material: floor, corner: [-3, 0, -3], u: [6, 0, 0], v: [0, 0, 6] }
  - { type: rectangle, material: lamp, corner: [-1, 3, -1], u: [2, 0, 0], v: [0, 0, 2] }
  - { type: sphere, material: bubble, center: [-0.9, 0.6, 0], radius: 0.5 }
  - { type: sphere, material: coat, center: [0.4, 0.5, -0.3], radius: 0.5 }
  - { type: sphere, material: flat, center: [1.3, 0.3, 0.6], radius: 0.3 }
  - { type: sphere, material: normals, center: [0.2, 0.25, 0.9], radius: 0.25 }
render: { width: 40, height: 30, spp: 4, max_depth: 5, tile_size: 16 }
)",
                                                        "materials.yaml", examples));
  return scenes;
}

}  // namespace tessera::device_tests
