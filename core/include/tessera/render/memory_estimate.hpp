#pragma once
// How much memory a job will take, counted from the scene description before any of it is
// built, so a service can refuse a job that cannot fit instead of attempting it.
#include <cstddef>
#include <string>

#include "tessera/scene/scene_description.hpp"

namespace tessera {

// What a scene holds, counted without building anything. A server counts it from the
// request (before converting it); scene_size() counts a description.
struct SceneSize {
  std::size_t triangles = 0;       // mesh triangles, every placement counted
  std::size_t vertices = 0;        // mesh vertices as described
  bool vertex_attributes = false;  // some mesh has normals or uvs
  std::size_t shapes = 0;          // every other geometry entry (spheres, quads, patches, ...)
  std::size_t patch_control_points = 0;
  std::size_t trim_points = 0;
  std::size_t environment_pixels = 0;
  std::size_t texture_pixels = 0;  // image textures, all together, before their mip levels
  std::size_t materials = 0;
  std::size_t lights = 0;
};

SceneSize scene_size(const SceneDescription& scene);

// Estimated peak bytes of one job, by what holds them. Calibrated against the measured peak
// RSS of tesserad preparing and rendering scenes (see README, "Budgets").
struct MemoryEstimate {
  std::size_t base = 0;         // what any job holds (buffers, caches, task arenas)
  std::size_t description = 0;  // the scene description the scene is prepared from
  std::size_t geometry = 0;     // render-ready triangles, their attributes, shapes, patches
  std::size_t accel = 0;        // BVH and triangle structures, with their build's peak
  std::size_t images = 0;       // environment and texture images, their tables and mip levels
  std::size_t film = 0;         // the whole image (only where one process assembles it)
  std::size_t tiles = 0;        // tiles in flight: one per thread, its planes and EXR bytes

  // The sum, saturating at the largest size_t (absurd counts must not wrap to small).
  std::size_t total() const;
  // "1.2 GiB (geometry 600 MiB, BVH 500 MiB, ...)": the largest parts named.
  std::string describe() const;
};

struct EstimateOptions {
  unsigned threads = 1;      // tiles rendered at once
  bool whole_image = false;  // the process also holds the assembled image (local renders)
};

MemoryEstimate estimate_memory(const SceneSize& size, const RenderSettings& settings,
                               const EstimateOptions& options = {});

// "512 MiB", "1.5 GiB", "900 KiB", "12 B".
std::string format_bytes(std::size_t bytes);

}  // namespace tessera
