#pragma once
// The Cornell box the integration tests render, at the size, spp and tile size a test needs.
#include <cstdint>
#include <string>

#include "tessera/scene/yaml_loader.hpp"

namespace tessera::test {

inline const std::string kCornell =
    std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml";

inline SceneDescription cornell(std::uint32_t width, std::uint32_t height, std::uint32_t spp,
                                std::uint32_t tile_size) {
  SceneDescription scene = load_scene_file(kCornell).scene;
  scene.render.width = width;
  scene.render.height = height;
  scene.render.samples_per_pixel = spp;
  scene.render.tile_size = tile_size;
  return scene;
}

}  // namespace tessera::test
