#pragma once
#include <string>
#include <vector>

#include "tessera/scene/scene_description.hpp"

namespace tessera::bench {

struct NamedScene {
  std::string name;
  SceneDescription scene;
};

// Procedural scenes for the specialisation benchmark, so it needs no data files:
// triangles only, analytic shapes only, a mix, and triangles under a sky (an environment light, no emitters).
std::vector<NamedScene> specialisation_scenes(std::uint32_t width, std::uint32_t height,
                                              std::uint32_t spp);

}  // namespace tessera::bench
