// gpu::path_tracer_kernels: what each path tracer kernel costs a multiprocessor (registers,
// local memory, resident blocks), read from the driver rather than from ptxas's report at
// build time, so a daemon's log and the GPU checks show the occupancy on the card in use.
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "path_tracer_kernel.cuh"
#include "tessera/gpu/gpu_renderer.hpp"

namespace tessera::gpu {

namespace {

template <unsigned kShapes>
KernelInfo describe(const char* name, const cudaDeviceProp& prop) {
  cudaFuncAttributes attributes{};
  int blocks = 0;
  check(cuda::path_tracer_tiles_resources<kShapes>(attributes, blocks), "kernel attributes");
  KernelInfo info;
  info.name = name;
  info.registers = attributes.numRegs;
  info.local_bytes = attributes.localSizeBytes;
  info.threads_per_block = static_cast<int>(cuda::kTileBlockEdge * cuda::kTileBlockEdge);
  info.blocks_per_multiprocessor = blocks;
  info.occupancy =
      prop.maxThreadsPerMultiProcessor > 0
          ? static_cast<double>(blocks * info.threads_per_block) / prop.maxThreadsPerMultiProcessor
          : 0.0;
  return info;
}

}  // namespace

std::vector<KernelInfo> path_tracer_kernels(int device) {
  check(cudaSetDevice(device), "cudaSetDevice");
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties");
  return {describe<cuda::kDeviceCommonShapes>("common shapes", prop),
          describe<cuda::kDeviceAllShapes>("all shapes", prop)};
}

}  // namespace tessera::gpu
