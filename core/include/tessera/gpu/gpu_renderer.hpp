#pragma once
// The GPU backend's host interface, free of CUDA types so that code built without nvcc can
// include it. Implemented in core/cuda/ (the tessera_cuda library, built when nvcc is found:
// TESSERA_CUDA=AUTO|ON); TESSERA_HAS_CUDA is defined for its users.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera::gpu {

struct DeviceInfo {
  int index = 0;
  std::string name;
  std::size_t memory_bytes = 0;
  int compute_major = 0, compute_minor = 0;
  int multiprocessors = 0;
};

// The CUDA devices this process can use; empty when there are none or no driver.
std::vector<DeviceInfo> list_devices();

// One of the path tracer's kernels as the driver loaded it on a device.
struct KernelInfo {
  std::string name;             // its feature set: "common shapes" or "all shapes"
  int registers = 0;            // per thread
  std::size_t local_bytes = 0;  // per thread: the stack and spills, in local memory
  int threads_per_block = 0;
  int blocks_per_multiprocessor = 0;  // resident at once
  double occupancy = 0.0;             // resident threads / the multiprocessor's most
};

// The path tracer's kernels on `device`, for the daemon's log and the GPU checks. Throws
// std::runtime_error naming the CUDA error.
std::vector<KernelInfo> path_tracer_kernels(int device);

// One job's scene uploaded to one device (PreparedScene::device_source), rendering tiles of
// its beauty pass and AOVs with the same samples the CPU draws. Not thread-safe: one per
// worker.
class TileRenderer {
 public:
  // Uploads the scene to `device`. Throws std::runtime_error naming the CUDA error, or
  // std::invalid_argument when the device path cannot render the scene (a patch, a trimmed
  // face, a shared mesh, an integrator other than the path tracer).
  TileRenderer(int device, std::shared_ptr<const PreparedScene> scene);
  ~TileRenderer();
  TileRenderer(const TileRenderer&) = delete;
  TileRenderer& operator=(const TileRenderer&) = delete;

  // Renders `tile` into `rgba` (tile.width * tile.height * 4 floats, overwritten), as
  // PreparedScene::render_tile does on the CPU. Throws std::runtime_error on a CUDA error; the
  // caller then renders the tile on the CPU.
  TileStats render_tile(const TileRect& tile, std::span<float> rgba);
  // Renders tiles[i] into rgba[i] (each tile.width * tile.height * 4 floats) in one kernel
  // launch, as render_tile does each; returns each tile's stats.
  std::vector<TileStats> render_tiles(std::span<const TileRect> tiles,
                                      std::span<const std::span<float>> rgba);
  // Renders `tile` into `passes` as PreparedScene::render_tile(tile, passes) does: the beauty
  // and every AOV plane the job asks for, sized to the tile, the others emptied.
  TileStats render_tile(const TileRect& tile, TilePasses& passes);
  // The same for tiles[i] into passes[i], in one kernel launch.
  std::vector<TileStats> render_tiles(std::span<const TileRect> tiles,
                                      std::span<TilePasses> passes);

  std::size_t uploaded_bytes() const;

 private:
  // Where one tile's planes go on the host: [0] the beauty, [1 + i] AOV i (aov_plane's
  // order); null for a plane the job does not ask for.
  using TileDestination = std::array<float*, 1 + kAovCount>;
  std::vector<TileStats> render_batch(std::span<const TileRect> tiles,
                                      std::span<const TileDestination> destinations);

  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tessera::gpu
