#pragma once
// The scheduler's GPU devices (server/tile_device.hpp) on the CUDA backend (core/cuda).
// Built only when tessera_cuda is (nvcc found: TESSERA_HAS_CUDA).
#include <memory>
#include <vector>

#include "server/tile_device.hpp"

namespace tessera::server {

// One device per CUDA GPU this process can use, each logged; none without a GPU or driver.
std::vector<std::shared_ptr<TileDevice>> gpu_tile_devices();

}  // namespace tessera::server
