#pragma once
// An equirectangular environment image in render form: its pixels (times the environment's
// colour and intensity) and the sampling tables of a 2D piecewise-constant distribution
// over them (math/piecewise_constant_2d.hpp), weighted by luminance times sin(theta) so
// that directions are drawn in proportion to the radiance they carry per solid angle.
#include <cstdint>
#include <vector>

#include "tessera/render/environment.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Owns the arrays an image Environment points into; they keep their addresses when moved.
struct EnvironmentMapTables {
  std::vector<float> pixels;  // linear RGB times the scale, rows from the zenith down
  std::vector<float> marginal_cdf;
  std::vector<float> conditional_cdf;
};

// Fills `tables` from the description's image and points `environment` (kind kImage) at
// them; `environment.scale` is the colour times intensity. The image must be valid
// (validate_scene checks it).
void build_environment_map(const EnvironmentDesc& description, Environment& environment,
                           EnvironmentMapTables& tables);

}  // namespace tessera
