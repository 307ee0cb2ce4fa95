#pragma once
// The device side of the path tracer: the same pipeline, programs and BVH traversal the
// CPU runs, compiled by nvcc from the shared headers. One thread renders all samples of
// one pixel, so film writes never race. Each .cu file of core/cuda instantiates one feature
// set (as the CPU compiles one variant per set), so nvcc compiles them in parallel;
// gpu::TileRenderer (path_tracer_device.cu) picks one per scene.
#include <cuda_runtime.h>

#include "tessera/render/path_tracer.hpp"
#include "tessera/render/pixel_sampling.hpp"

namespace tessera::cuda {

// The feature sets compiled for the device. Neither holds the shapes
// PreparedScene::device_source refuses (patches and trimmed faces point into host memory):
// their intersection code (Bézier clipping, trim loops) made most of an all-features
// kernel's per-thread stack (29 KB with them). -Xptxas -v for sm_90 (8 December, the
// batched kernel with the compressed BVH walk): kDeviceCommonShapes 2,288 bytes of stack
// and 255 registers, 324 bytes of spills; kDeviceAllShapes 6,080 bytes and 255 registers,
// 1.5 KB of spills. (5,536 and 9,312 bytes while the programs held copies of the scene,
// its camera and its shape arrays.)
// Kernels are templates on the shape mask alone (nvcc's launch stubs take no class-type
// template arguments); every other feature is on.
inline constexpr unsigned kDeviceCommonShapes = kCommonShapes;
inline constexpr unsigned kDeviceAllShapes = kAllShapes & ~(kShapePatch | kShapeTrimmed);

// Never interrupts: a device tile is cancelled by not launching it.
struct NeverInterrupted {
  __device__ bool operator()() const { return false; }
};

// Threads per block edge of the tile kernels: 8 x 8 pixels.
inline constexpr unsigned kTileBlockEdge = 8;

// One thread per pixel of a batch of tiles: blockIdx.z picks the tile, so a batch of a
// job's tiles fills the device in one launch where one 16x16 tile gives it 256 threads.
// The scene stays a __grid_constant__ parameter, which the programs hold by reference: a
// plain parameter whose address is taken is copied to every thread's stack.
template <unsigned kShapes>
__global__ void path_tracer_tiles_kernel(const __grid_constant__ SceneView scene,
                                         std::uint64_t seed, PixelSampling sampling,
                                         std::uint32_t max_depth, SamplerKind sampler,
                                         LightStrategy strategy, float clamp,
                                         bool transparent_background, const TileRect* tiles,
                                         const FilmPlanes* films, unsigned long long* ray_counts) {
  const TileRect tile = tiles[blockIdx.z];
  const FilmPlanes film = films[blockIdx.z];
  const std::uint32_t local_x = blockIdx.x * blockDim.x + threadIdx.x;
  const std::uint32_t local_y = blockIdx.y * blockDim.y + threadIdx.y;
  if (local_x >= tile.width || local_y >= tile.height) return;
  constexpr PipelineFeatures kFeatures{kShapes, true, true, true};
  std::uint64_t rays = 0;
  const PathRayGeneration<kFeatures.aovs> generation{
      scene.camera, seed, tile, sampling.sample_weight(), film, &rays, sampler};
  const BvhTracer<SceneIntersection<kFeatures.shapes>> tracer(
      scene.bvh, SceneIntersection<kFeatures.shapes>{scene});
  const Pipeline<PathTracerConfig<kFeatures>> pipeline(
      generation, tracer, PathHit<kFeatures>{scene, max_depth, strategy, clamp},
      PathMiss<kFeatures>{scene, strategy, transparent_background, clamp});
  NeverInterrupted interrupted;
  render_pixel(pipeline, tile.x + local_x, tile.y + local_y, tile, film, sampling, interrupted);
  atomicAdd(&ray_counts[blockIdx.z], static_cast<unsigned long long>(rays));
}

// Renders `count` tiles of one job on the current device with the kernel of kShapes, each
// pixel as the CPU does (render_pixel: adaptive sampling and refinement included): tile i
// is tiles[i] into films[i], its rays added to ray_counts[i]. Every pointer must be device
// memory, the arrays included; `largest_width` and `largest_height` bound the tiles. The
// films' depth planes must start at +inf and the others at 0, as PreparedScene::render_tile
// sets them. `clamp` and `transparent_background` are the render settings'. Returns the
// launch status. Instantiated once per feature set, each in its own .cu file.
template <unsigned kShapes>
cudaError_t launch_path_tracer_tiles(const SceneView& scene, std::uint64_t seed,
                                     const PixelSampling& sampling, std::uint32_t max_depth,
                                     SamplerKind sampler, LightStrategy strategy, float clamp,
                                     bool transparent_background, const TileRect* tiles,
                                     const FilmPlanes* films, std::uint32_t count,
                                     std::uint32_t largest_width, std::uint32_t largest_height,
                                     unsigned long long* ray_counts, cudaStream_t stream) {
  const dim3 block(kTileBlockEdge, kTileBlockEdge);
  const dim3 grid((largest_width + block.x - 1) / block.x, (largest_height + block.y - 1) / block.y,
                  count);
  path_tracer_tiles_kernel<kShapes>
      <<<grid, block, 0, stream>>>(scene, seed, sampling, max_depth, sampler, strategy, clamp,
                                   transparent_background, tiles, films, ray_counts);
  return cudaGetLastError();
}

// The kernel of kShapes as compiled (registers and local memory per thread, from
// cudaFuncGetAttributes) and how many of its blocks one multiprocessor of the current device
// holds at once. Instantiated with launch_path_tracer_tiles.
template <unsigned kShapes>
cudaError_t path_tracer_tiles_resources(cudaFuncAttributes& attributes,
                                        int& blocks_per_multiprocessor) {
  const cudaError_t status = cudaFuncGetAttributes(&attributes, path_tracer_tiles_kernel<kShapes>);
  if (status != cudaSuccess) return status;
  return cudaOccupancyMaxActiveBlocksPerMultiprocessor(
      &blocks_per_multiprocessor, path_tracer_tiles_kernel<kShapes>,
      static_cast<int>(kTileBlockEdge * kTileBlockEdge), 0);
}

// Instantiated in kernel_common_shapes.cu and kernel_all_shapes.cu alone, so the files that
// launch them do not compile the kernels again.
#define TESSERA_DEVICE_LAUNCH(shapes)                                                    \
  cudaError_t launch_path_tracer_tiles<shapes>(                                          \
      const SceneView&, std::uint64_t, const PixelSampling&, std::uint32_t, SamplerKind, \
      LightStrategy, float, bool, const TileRect*, const FilmPlanes*, std::uint32_t,     \
      std::uint32_t, std::uint32_t, unsigned long long*, cudaStream_t)
extern template TESSERA_DEVICE_LAUNCH(kDeviceCommonShapes);
extern template TESSERA_DEVICE_LAUNCH(kDeviceAllShapes);

#define TESSERA_DEVICE_RESOURCES(shapes) \
  cudaError_t path_tracer_tiles_resources<shapes>(cudaFuncAttributes&, int&)
extern template TESSERA_DEVICE_RESOURCES(kDeviceCommonShapes);
extern template TESSERA_DEVICE_RESOURCES(kDeviceAllShapes);

}  // namespace tessera::cuda
