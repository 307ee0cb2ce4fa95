#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

// The channels of a job's output image: R, G, B, A, then for each AOV asked for, in
// aov_names() order: Albedo.R/G/B, Normal.X/Y/Z, Z (depth), PrimitiveID.X,
// Variance.R/G/B, SampleCount.X. The names are
// the ones compositors map: Z is OpenEXR's depth channel, which Nuke reads as depth.Z and
// Blender's Image node as its Depth output; Normal.X/Y/Z is Blender's Normal pass (layer
// "Normal", components X, Y, Z); Albedo.R/G/B follows the same layer.component pattern;
// PrimitiveID.X is a UINT channel (is_id_channel), named after Blender's IndexOB.X;
// Variance.R/G/B and SampleCount.X (adaptive sampling's estimate and count) follow the same
// pattern. One
// EXR per tile carries all of them, so a tile still arrives exactly once.
std::vector<std::string> output_channels(std::uint32_t aovs);

// A tile's passes interleaved per pixel in output_channels(aovs) order.
std::vector<float> interleave_passes(const TilePasses& passes, std::uint32_t aovs);

}  // namespace tessera
