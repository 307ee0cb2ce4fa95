#pragma once
// The bytes a job store keeps for a tile between its passes (TileAccumulation: partial
// sums of every plane, the variance's running statistics, samples done), so a restarted
// daemon continues the tile exactly where its last stored pass ended.
#include <cstdint>
#include <vector>

#include "tessera/render/tile_accumulation.hpp"

namespace tessera::server {

// Layout: "TAC1", then samples_done, samples_total, floats per plane and a mask of the
// planes present (bit 0 beauty, bits 1-6 the AOVs in aov_names() order, 7 running mean,
// 8 running m2), each a little-endian uint32; then the planes' floats in bit order, raw
// (IEEE 754, the host's byte order: the store is local to the machine that wrote it).
std::vector<std::uint8_t> encode_tile_state(const TileAccumulation& state);
// Throws std::runtime_error for bytes that are not a state of this layout.
TileAccumulation decode_tile_state(const std::vector<std::uint8_t>& bytes);

}  // namespace tessera::server
