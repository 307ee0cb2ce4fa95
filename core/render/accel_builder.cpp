#include "tessera/render/accel_builder.hpp"

#include <stdexcept>
#include <string>

namespace tessera {

AccelBuildOptions accel_build_options(std::string_view accel_builder) {
  AccelBuildOptions options;
  if (accel_builder.empty() || accel_builder == "auto") return options;
  if (accel_builder == "spatial") {
    options.presplit_budget = 0.0f;
    options.spatial_split_budget = kAutoSpatialSplitBudget;
    return options;
  }
  if (accel_builder == "binned") {
    options.presplit_budget = 0.0f;
    options.spatial_split_budget = 0.0f;
    return options;
  }
  throw std::invalid_argument("render.accel_builder: \"" + std::string(accel_builder) +
                              "\" is not one of auto, spatial, binned");
}

}  // namespace tessera
