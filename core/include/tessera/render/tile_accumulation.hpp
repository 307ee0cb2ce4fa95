#pragma once
// A tile rendered in passes: the state kept between passes and the image it shows after
// each. PreparedScene::accumulate_tile adds a pass; a job with N passes renders samples
// [0, spp) of every tile in N contiguous ranges (pass_sample_end).
#include <cstdint>
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

// The partial sums of a tile's planes after `samples_done` of `samples_total` samples, every
// sample added at its weight in the whole render (1 / samples_total). Kept as sums rather
// than as an image so that no pass rescales what the earlier ones added: after the last
// pass the planes are, bit for bit, those one render_tile of samples_total gives.
struct TileAccumulation {
  std::uint32_t samples_done = 0;
  std::uint32_t samples_total = 0;
  TilePasses sums;
  // The variance AOV's running statistics per pixel (RGBA, RGB used): mean and sum of
  // squared deviations. Empty unless the job asked for the variance AOV.
  std::vector<float> running_mean;
  std::vector<float> running_m2;
};

// Samples done after pass `pass` (1-based) of `passes` that split `samples` evenly (the
// earlier passes take the remainder's share one sample less). Pass `passes` ends at
// `samples`. Requires 1 <= pass <= passes <= samples.
std::uint32_t pass_sample_end(std::uint32_t samples, std::uint32_t passes, std::uint32_t pass);

// The tile's image after the samples done: the sums scaled to an average (beauty, albedo,
// normal), the rest (depth, IDs, variance, sample count) as they are. After the last pass
// the sums are returned unscaled, so the image is exactly the single render's.
TilePasses accumulated_image(const TileAccumulation& state);

}  // namespace tessera
