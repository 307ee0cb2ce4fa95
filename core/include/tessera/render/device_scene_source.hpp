#pragma once
// A job's scene as a GPU backend uploads it. The CPU traces mesh triangles through its SIMD
// structure (BvhView::triangles) and the other shapes through an eight-wide tree; device
// code walks one BVH and reads nothing else. The device layout is therefore a second BVH
// over every visible bounded primitive, mesh triangles included (binary, and compressed
// into eight-wide nodes for closest and any hits), beside the flat arrays the CPU already
// has, and a list of the buffers to copy: each one a host array and the SceneView pointer
// its device copy replaces. Meshes placed more than once, which the CPU traces through an
// instance level, are baked into world triangles there.
//
// PreparedScene::device_source builds it; PreparedScene::render_tile_device_layout renders
// through it on the CPU, so the layout is tested on machines without a GPU (the walk, the
// arrays and the pipeline are the code nvcc compiles for the device).
#include <cstddef>
#include <string>
#include <vector>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/compressed_wide_bvh.hpp"
#include "tessera/render/scene_data.hpp"

namespace tessera {

struct DeviceBuffer {
  const void* host = nullptr;
  std::size_t bytes = 0;
  // Points the view's field at the buffer's copy (host or device memory).
  void (*assign)(SceneView& view, const void* copy) = nullptr;
};

struct DeviceSceneSource {
  // Host pointers throughout; the BVH is `bvh`, with no SIMD triangles, instance levels or
  // wide nodes, as device code sees it.
  SceneView view;
  std::vector<DeviceBuffer> buffers;
  Bvh bvh;  // over every visible bounded primitive; `view.bvh` and a buffer point into it
  // `bvh` in compressed eight-wide nodes (accel/compressed_wide_bvh.hpp), which closest-
  // and any-hit queries walk; all-hits queries walk `bvh`. Empty where it cannot be built.
  CompressedWideBvh compressed;
  // When meshes are placed more than once: the scene's triangles with every placement baked
  // after them (render/baked_placements.hpp), and their attributes when any are stored;
  // `view.triangles` and `view.triangle_attributes` and their buffers point here. Otherwise
  // empty, and they point at the scene's own.
  std::vector<Triangle> triangles;
  std::vector<TriangleAttributes> triangle_attributes;
  // Empty when the device path renders this scene as the CPU does; otherwise why it cannot
  // (the scheduler then keeps the job's tiles on the CPU), and nothing else is built.
  std::string unsupported;

  std::size_t bytes() const {
    std::size_t total = 0;
    for (const DeviceBuffer& b : buffers) total += b.bytes;
    return total;
  }
};

}  // namespace tessera
