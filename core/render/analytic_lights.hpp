#pragma once
// The scene's lights that are not shapes, and its environment, in render form
// (render/analytic_light.hpp, render/environment.hpp), from the description's `lights` and
// `environment` (or background).
#include <cstdint>
#include <vector>

#include "environment_map.hpp"
#include "tessera/render/analytic_light.hpp"
#include "tessera/render/environment.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

struct AnalyticLightSet {
  // Point and spot lights in input order, then distant lights, then the environment
  // (when it is not black): the order SceneView::analytic_lights promises.
  std::vector<AnalyticLight> lights;
  std::uint32_t first_infinite = 0;  // index of the first distant light or environment
  Environment environment;
  EnvironmentMapTables environment_tables;  // what an image environment points into
};

AnalyticLightSet make_analytic_lights(const SceneDescription& description);

}  // namespace tessera
