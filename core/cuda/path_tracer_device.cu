// The device side of the path tracer: the same pipeline, programs and BVH traversal the
// CPU runs, compiled by nvcc from the shared headers. One thread renders all samples of
// one pixel, so film writes never race. The GPU backend's scheduler (a later issue) uploads
// the SceneView arrays and calls launch_path_tracer_tile.
#include <cuda_runtime.h>

#include "tessera/render/path_tracer.hpp"
#include "tessera/render/pixel_sampling.hpp"

namespace tessera::cuda {

namespace {

// Every feature on: the device build proves the whole pipeline compiles for the GPU.
constexpr PipelineFeatures kDeviceFeatures = kAllFeatures;
using DeviceConfig = PathTracerConfig<kDeviceFeatures>;

// Never interrupts: a device tile is cancelled by not launching it.
struct NeverInterrupted {
  __device__ bool operator()() const { return false; }
};

__global__ void path_tracer_tile_kernel(SceneView scene, std::uint64_t seed, PixelSampling sampling,
                                        std::uint32_t max_depth, SamplerKind sampler,
                                        LightStrategy strategy, float clamp,
                                        bool transparent_background, TileRect tile, FilmPlanes film,
                                        unsigned long long* ray_count) {
  const std::uint32_t local_x = blockIdx.x * blockDim.x + threadIdx.x;
  const std::uint32_t local_y = blockIdx.y * blockDim.y + threadIdx.y;
  if (local_x >= tile.width || local_y >= tile.height) return;
  std::uint64_t rays = 0;
  const PathRayGeneration<kDeviceFeatures.aovs> generation{
      scene.camera, seed, tile, sampling.sample_weight(), film, &rays, sampler};
  const BvhTracer<SceneIntersection<kDeviceFeatures.shapes>> tracer(
      scene.bvh, SceneIntersection<kDeviceFeatures.shapes>{scene});
  const Pipeline<DeviceConfig> pipeline(
      generation, tracer, PathHit<kDeviceFeatures>{scene, max_depth, strategy, clamp},
      PathMiss<kDeviceFeatures>{scene, strategy, transparent_background, clamp});
  NeverInterrupted interrupted;
  render_pixel(pipeline, tile.x + local_x, tile.y + local_y, tile, film, sampling, interrupted);
  atomicAdd(ray_count, static_cast<unsigned long long>(rays));
}

}  // namespace

// Renders one tile on the current device, each pixel as the CPU does (render_pixel:
// adaptive sampling and refinement included). Every pointer in `scene` and `film` must be
// device memory; `ray_count` too. `clamp` and `transparent_background` are the render
// settings'. The film's depth plane must start at +inf and the others at 0, as
// PreparedScene::render_tile sets them. Returns the launch status.
cudaError_t launch_path_tracer_tile(const SceneView& scene, std::uint64_t seed,
                                    const PixelSampling& sampling, std::uint32_t max_depth,
                                    SamplerKind sampler, LightStrategy strategy, float clamp,
                                    bool transparent_background, const TileRect& tile,
                                    const FilmPlanes& film, unsigned long long* ray_count,
                                    cudaStream_t stream) {
  const dim3 block(8, 8);
  const dim3 grid((tile.width + block.x - 1) / block.x, (tile.height + block.y - 1) / block.y);
  path_tracer_tile_kernel<<<grid, block, 0, stream>>>(scene, seed, sampling, max_depth, sampler,
                                                      strategy, clamp, transparent_background, tile,
                                                      film, ray_count);
  return cudaGetLastError();
}

}  // namespace tessera::cuda
