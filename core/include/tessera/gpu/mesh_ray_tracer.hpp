#pragma once
// Closest hits of rays against a triangle mesh on a CUDA device, one thread per ray, through
// the device layout's BVH walks alone: the benchmark and test of the GPU's traversal apart
// from shading (tessera-bench gpu-trace). Free of CUDA types like gpu_renderer.hpp;
// implemented in core/cuda/mesh_ray_tracer.cu.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tessera/geometry/triangle.hpp"

namespace tessera::gpu {

// Which form of the BVH the kernel walks: the compressed eight-wide nodes the path tracer
// walks (accel/compressed_wide_bvh.hpp), or the binary tree they are built from.
enum class DeviceWalk : std::uint8_t { kCompressed, kBinary };

struct DeviceTraceResult {
  std::vector<float> t;       // per ray: the closest hit's distance, +inf on a miss
  double best_seconds = 0.0;  // the fastest kernel run (CUDA events), excluding copies
};

class MeshRayTracer {
 public:
  // Builds the BVH as PreparedScene::device_source does (degenerate triangles left out),
  // and uploads it with the triangles to `device`. Throws std::runtime_error naming the
  // CUDA error (no device, no driver, out of memory).
  MeshRayTracer(int device, std::span<const Triangle> triangles);
  ~MeshRayTracer();
  MeshRayTracer(const MeshRayTracer&) = delete;
  MeshRayTracer& operator=(const MeshRayTracer&) = delete;

  // Traces every ray `repeat` times (at least once) with `walk`.
  DeviceTraceResult trace(std::span<const Ray> rays, DeviceWalk walk, unsigned repeat);

  std::size_t uploaded_bytes() const;  // triangles, both trees and their references

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tessera::gpu
