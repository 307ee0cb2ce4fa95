#pragma once
// The backend's one way of turning a CUDA status into an exception that names the call, so
// a device error reaches the scheduler (which renders the tile on the CPU) with its reason.
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace tessera::gpu {

inline void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess)
    throw std::runtime_error(std::string("CUDA ") + what + ": " + cudaGetErrorString(status));
}

}  // namespace tessera::gpu
