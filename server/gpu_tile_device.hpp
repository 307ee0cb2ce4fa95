#pragma once
// The scheduler's GPU devices (server/tile_device.hpp) on the CUDA backend (core/cuda).
// Built only when tessera_cuda is (nvcc found: TESSERA_HAS_CUDA).
#include <cstddef>
#include <memory>
#include <vector>

#include "server/tile_device.hpp"

namespace tessera::server {

// One device per CUDA GPU this process can use, each logged; none without a GPU or driver.
// Each takes batches of up to `batch_pixels` pixels per launch; 0: multiprocessors x 1024.
std::vector<std::shared_ptr<TileDevice>> gpu_tile_devices(std::size_t batch_pixels = 0);

}  // namespace tessera::server
