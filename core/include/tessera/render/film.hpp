#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>

#include "tessera/geometry/ray.hpp"
#include "tessera/math/vec.hpp"
#include "tessera/render/tile.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// The tile's output planes, each tile.width * tile.height RGBA floats; null when not asked for.
struct FilmPlanes {
  float* beauty = nullptr;  // A: coverage, the share of samples whose camera ray hit a surface
  float* albedo = nullptr;
  float* normal = nullptr;
  // Distance along the camera ray to the nearest surface any sample saw, in R, G and B;
  // +inf where none hit (starts at +inf: depth is a minimum, not an average, because an
  // average of a foreground and a background distance is a surface that is not there).
  float* depth = nullptr;
  // First sample's primitive reference + 1 (0 = background) as a 32-bit unsigned integer:
  // the float slot carries the integer's bits (id_as_float), so it survives unrounded to
  // the EXR's UINT channel. A float holds integers exactly only up to 2^24.
  float* primitive_id = nullptr;
  float* variance = nullptr;      // variance of the pixel's mean, per channel
  float* sample_count = nullptr;  // samples the pixel took, in R, G and B
  // Progressive refinement: the planes already hold the image of samples [0, first_sample),
  // and the render adds the samples from there on.
  std::uint32_t first_sample = 0;
  // Accumulation in passes (PreparedScene::accumulate_tile): when not 0, every sample is
  // added at its weight in a render of `total_samples`, and the planes hold the partial
  // sums of that render rather than an image (no rescaling between passes, so the last
  // pass ends with the very floats a single render gives). The variance AOV's running
  // statistics then live between passes in these two planes (mean and sum of squared
  // deviations, RGB of RGBA); null when the variance AOV is off.
  std::uint32_t total_samples = 0;
  float* running_mean = nullptr;
  float* running_m2 = nullptr;

  TESSERA_HD static std::size_t offset(const TileRect& tile, std::uint32_t x, std::uint32_t y) {
    return 4 * ((static_cast<std::size_t>(y) - tile.y) * tile.width + (x - tile.x));
  }
  TESSERA_HD static void add(float* plane, std::size_t at, const vec3& value, float weight) {
    plane[at] += value.x * weight;
    plane[at + 1] += value.y * weight;
    plane[at + 2] += value.z * weight;
  }
  TESSERA_HD static void keep_nearest(float* plane, std::size_t at, float depth) {
    if (depth < plane[at]) plane[at] = plane[at + 1] = plane[at + 2] = depth;
  }
};

// The plane of AOV `index`, in aov_names() order (albedo, normal, depth, primitive id,
// variance, sample count), so code that lays out a job's planes walks the AOV bits.
inline float*& aov_plane(FilmPlanes& film, std::size_t index) {
  float** planes[] = {&film.albedo,       &film.normal,   &film.depth,
                      &film.primitive_id, &film.variance, &film.sample_count};
  static_assert(std::size(planes) == kAovCount);
  return *planes[index];
}

// What AOV `index`'s plane starts at: depth keeps the nearest sample, so it starts
// infinitely far; the others are sums.
inline float aov_start(std::size_t index) {
  return (1u << index) == kAovDepth ? kInfinity : 0.0f;
}

// A 32-bit integer carried in a float's bits (and back), for ID planes.
TESSERA_HD inline float id_as_float(std::uint32_t id) {
  float bits;
  std::memcpy(&bits, &id, sizeof bits);
  return bits;
}
TESSERA_HD inline std::uint32_t float_as_id(float bits) {
  std::uint32_t id;
  std::memcpy(&id, &bits, sizeof id);
  return id;
}

// First-hit data recorded for the AOV planes.
struct FirstHitAovs {
  vec3 albedo{0.0f};
  vec3 normal{0.0f};
  float depth = kInfinity;  // a miss is infinitely far
  std::uint32_t primitive = 0xffffffffU;
};

}  // namespace tessera
