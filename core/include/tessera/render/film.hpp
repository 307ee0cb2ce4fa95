#pragma once
#include <cstdint>

#include "tessera/math/vec.hpp"
#include "tessera/render/tile.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// The tile's output planes, each tile.width * tile.height RGBA floats; null when not asked for.
struct FilmPlanes {
  float* beauty = nullptr;
  float* albedo = nullptr;
  float* normal = nullptr;
  float* depth = nullptr;         // distance along the camera ray, in R, G and B
  float* primitive_id = nullptr;  // first sample's primitive index + 1 (0 = background)
  float* variance = nullptr;      // variance of the pixel's mean, per channel
  float* sample_count = nullptr;  // samples the pixel took, in R, G and B
  // Progressive refinement: the planes already hold the image of samples [0, first_sample),
  // and the render adds the samples from there on.
  std::uint32_t first_sample = 0;

  TESSERA_HD static std::size_t offset(const TileRect& tile, std::uint32_t x, std::uint32_t y) {
    return 4 * ((static_cast<std::size_t>(y) - tile.y) * tile.width + (x - tile.x));
  }
  TESSERA_HD static void add(float* plane, std::size_t at, const vec3& value, float weight) {
    plane[at] += value.x * weight;
    plane[at + 1] += value.y * weight;
    plane[at + 2] += value.z * weight;
  }
};

// First-hit data recorded for the AOV planes.
struct FirstHitAovs {
  vec3 albedo{0.0f};
  vec3 normal{0.0f};
  float depth = 0.0f;
  std::uint32_t primitive = 0xffffffffU;
};

}  // namespace tessera
