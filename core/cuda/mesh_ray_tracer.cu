// gpu::MeshRayTracer: the device layout's BVH walks on their own, one thread per ray.
#include <cuda_runtime.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/accel/compressed_wide_bvh.hpp"
#include "tessera/accel/triangle_bvh.hpp"
#include "tessera/gpu/mesh_ray_tracer.hpp"

namespace tessera::gpu {

namespace {

template <typename T>
T* upload(const T* host, std::size_t count, std::vector<void*>& owned) {
  void* pointer = nullptr;
  const std::size_t bytes = std::max<std::size_t>(count, 1) * sizeof(T);
  check(cudaMalloc(&pointer, bytes), "cudaMalloc");
  owned.push_back(pointer);
  if (count > 0)
    check(cudaMemcpy(pointer, host, count * sizeof(T), cudaMemcpyHostToDevice), "cudaMemcpy");
  return static_cast<T*>(pointer);
}

template <bool kCompressed>
__global__ void closest_hit_kernel(BvhView bvh, const Triangle* triangles, const Ray* rays,
                                   std::uint32_t count, float* t_out) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const Ray ray = rays[i];
  HitRecord hit;
  hit.t = ray.t_max;
  const auto test = [triangles](std::uint32_t ref, const Ray& r, float t_max, HitRecord& h) {
    return intersect(triangles[ref], r, t_max, h, ref);
  };
  bool found;
  if constexpr (kCompressed)
    found = traverse_compressed_wide<false>(bvh, ray, hit, test);
  else
    found = traverse_bvh<false>(bvh, ray, hit, test);
  t_out[i] = found ? hit.t : kInfinity;
}

}  // namespace

struct MeshRayTracer::State {
  int device = 0;
  std::vector<void*> owned;  // device allocations, freed with the tracer
  BvhView view;              // device pointers
  const Triangle* triangles = nullptr;
  std::size_t uploaded = 0;
};

MeshRayTracer::MeshRayTracer(int device, std::span<const Triangle> triangles)
    : state_(std::make_unique<State>()) {
  const Bvh binary = build_triangle_bvh(triangles);
  const CompressedWideBvh compressed = compress_bvh(binary);
  State& s = *state_;
  s.device = device;
  check(cudaSetDevice(device), "cudaSetDevice");
  s.triangles = upload(triangles.data(), triangles.size(), s.owned);
  s.view.nodes = upload(binary.nodes.data(), binary.nodes.size(), s.owned);
  s.view.primitives = upload(binary.primitives.data(), binary.primitives.size(), s.owned);
  s.view.node_count = static_cast<std::uint32_t>(binary.nodes.size());
  if (!compressed.nodes.empty()) {
    s.view.compressed_nodes = upload(compressed.nodes.data(), compressed.nodes.size(), s.owned);
    s.view.compressed_primitives =
        upload(compressed.primitives.data(), compressed.primitives.size(), s.owned);
  }
  s.uploaded = triangles.size() * sizeof(Triangle) + binary.nodes.size() * sizeof(BvhNode) +
               binary.primitives.size() * 4 + compressed.nodes.size() * sizeof(CompressedWideNode) +
               compressed.primitives.size() * 4;
}

MeshRayTracer::~MeshRayTracer() {
  if (!state_) return;
  cudaSetDevice(state_->device);
  for (void* pointer : state_->owned) cudaFree(pointer);
}

std::size_t MeshRayTracer::uploaded_bytes() const {
  return state_->uploaded;
}

DeviceTraceResult MeshRayTracer::trace(std::span<const Ray> rays, DeviceWalk walk,
                                       unsigned repeat) {
  State& s = *state_;
  DeviceTraceResult result;
  result.t.assign(rays.size(), kInfinity);
  if (rays.empty() || s.view.node_count == 0) return result;
  if (walk == DeviceWalk::kCompressed && s.view.compressed_nodes == nullptr)
    throw std::invalid_argument("MeshRayTracer: this mesh's tree has no compressed form");
  check(cudaSetDevice(s.device), "cudaSetDevice");
  std::vector<void*> scratch;
  struct Free {
    std::vector<void*>& pointers;
    ~Free() {
      for (void* p : pointers) cudaFree(p);
    }
  } free_scratch{scratch};
  const Ray* device_rays = upload(rays.data(), rays.size(), scratch);
  float* device_t = nullptr;
  check(cudaMalloc(reinterpret_cast<void**>(&device_t), rays.size() * sizeof(float)), "cudaMalloc");
  scratch.push_back(device_t);
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "cudaEventCreate");
  check(cudaEventCreate(&stop), "cudaEventCreate");
  const auto count = static_cast<std::uint32_t>(rays.size());
  constexpr std::uint32_t kBlock = 128;
  const std::uint32_t blocks = (count + kBlock - 1) / kBlock;
  float best_ms = 0.0f;
  for (unsigned run = 0; run < std::max(1u, repeat); ++run) {
    check(cudaEventRecord(start), "cudaEventRecord");
    if (walk == DeviceWalk::kCompressed)
      closest_hit_kernel<true>
          <<<blocks, kBlock>>>(s.view, s.triangles, device_rays, count, device_t);
    else
      closest_hit_kernel<false>
          <<<blocks, kBlock>>>(s.view, s.triangles, device_rays, count, device_t);
    check(cudaGetLastError(), "kernel launch");
    check(cudaEventRecord(stop), "cudaEventRecord");
    check(cudaEventSynchronize(stop), "trace kernel");
    float ms = 0.0f;
    check(cudaEventElapsedTime(&ms, start, stop), "cudaEventElapsedTime");
    best_ms = run == 0 ? ms : std::min(best_ms, ms);
  }
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  check(cudaMemcpy(result.t.data(), device_t, rays.size() * sizeof(float), cudaMemcpyDeviceToHost),
        "cudaMemcpy (hits)");
  result.best_seconds = best_ms * 1e-3;
  return result;
}

}  // namespace tessera::gpu
