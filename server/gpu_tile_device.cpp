#include "server/gpu_tile_device.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <string>

#include "tessera/gpu/gpu_renderer.hpp"

namespace tessera::server {

namespace {

// A job's scene is uploaded when the device takes its first tile and stays until the device
// takes a tile of another job (one worker thread per device, so no locking): a job's tiles
// mostly come in a run, and a re-upload costs only copies.
class GpuTileDevice : public TileDevice {
 public:
  GpuTileDevice(const gpu::DeviceInfo& info, std::size_t batch_pixels)
      : info_(info),
        name_("gpu" + std::to_string(info.index) + " " + info.name),
        batch_pixels_(batch_pixels != 0
                          ? batch_pixels
                          : static_cast<std::size_t>(std::max(1, info.multiprocessors)) * 1024) {}

  std::string name() const override { return name_; }

  bool accepts(const PreparedScene& scene) const override {
    const DeviceSceneSource& source = scene.device_source();
    // Leaves a fifth of the device's memory to the film, the stack and the driver.
    return source.unsupported.empty() && source.bytes() < info_.memory_bytes / 5 * 4;
  }

  TileStats render_tile(const std::shared_ptr<const PreparedScene>& scene, const TileRect& tile,
                        TilePasses& passes) override {
    return renderer_for(scene).render_tile(tile, passes);
  }

  // By default about four pixels per thread the multiprocessors keep in flight at the path
  // tracer's 255 registers (eight warps each): enough to fill the device between launches,
  // few enough that the CPU threads still share a job's last tiles. Not yet tuned on a GPU
  // (the daemon's gpu_batch_pixels overrides it).
  std::size_t batch_pixels() const override { return batch_pixels_; }

  std::vector<TileStats> render_tiles(const std::shared_ptr<const PreparedScene>& scene,
                                      std::span<const TileRect> tiles,
                                      std::span<TilePasses> passes) override {
    return renderer_for(scene).render_tiles(tiles, passes);
  }

 private:
  gpu::TileRenderer& renderer_for(const std::shared_ptr<const PreparedScene>& scene) {
    if (scene != scene_) {
      renderer_.reset();
      scene_.reset();
      renderer_ = std::make_unique<gpu::TileRenderer>(info_.index, scene);
      scene_ = scene;
      spdlog::debug("{}: scene uploaded, {:.1f} MiB", name_,
                    static_cast<double>(renderer_->uploaded_bytes()) / (1 << 20));
    }
    return *renderer_;
  }

  gpu::DeviceInfo info_;
  std::string name_;
  std::size_t batch_pixels_;
  std::shared_ptr<const PreparedScene> scene_;
  std::unique_ptr<gpu::TileRenderer> renderer_;
};

}  // namespace

std::vector<std::shared_ptr<TileDevice>> gpu_tile_devices(std::size_t batch_pixels) {
  std::vector<std::shared_ptr<TileDevice>> devices;
  for (const gpu::DeviceInfo& info : gpu::list_devices()) {
    spdlog::info("GPU {}: {}, {:.1f} GiB, compute capability {}.{}, {} multiprocessors", info.index,
                 info.name, static_cast<double>(info.memory_bytes) / (1 << 30), info.compute_major,
                 info.compute_minor, info.multiprocessors);
    try {
      for (const gpu::KernelInfo& kernel : gpu::path_tracer_kernels(info.index))
        spdlog::info(
            "GPU {}: {} kernel: {} registers and {} bytes of local memory per thread, {} "
            "blocks of {} threads per multiprocessor ({:.1f}% occupancy)",
            info.index, kernel.name, kernel.registers, kernel.local_bytes,
            kernel.blocks_per_multiprocessor, kernel.threads_per_block, 100.0 * kernel.occupancy);
    } catch (const std::exception& e) {
      spdlog::warn("GPU {}: cannot read its kernels' resources: {}", info.index, e.what());
    }
    devices.push_back(std::make_shared<GpuTileDevice>(info, batch_pixels));
  }
  return devices;
}

}  // namespace tessera::server
