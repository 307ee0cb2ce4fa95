#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

// The channels of a job's output image: R, G, B, A, then for each AOV asked for, in
// aov_names() order: albedo.R/G/B, normal.X/Y/Z, Z (depth), primitive_id,
// variance.R/G/B, sample_count. One EXR per tile
// carries all of them, so a tile still arrives exactly once.
std::vector<std::string> output_channels(std::uint32_t aovs);

// A tile's passes interleaved per pixel in output_channels(aovs) order.
std::vector<float> interleave_passes(const TilePasses& passes, std::uint32_t aovs);

}  // namespace tessera
