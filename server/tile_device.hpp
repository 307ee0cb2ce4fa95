#pragma once
// A device beside the CPU threads that renders whole tiles: a GPU (server/gpu_tile_device.hpp)
// or, in tests, a stand-in. The scheduler gives each device a worker thread of its own that
// takes tiles from the same queue as the CPU workers, so a faster device simply takes more of
// them. A per-tile virtual call: nothing here runs per ray.
#include <memory>
#include <span>
#include <string>

#include "tessera/render/prepared_scene.hpp"

namespace tessera::server {

class TileDevice {
 public:
  virtual ~TileDevice() = default;
  // How logs and metrics name it ("gpu0 NVIDIA H100 80GB HBM3").
  virtual std::string name() const = 0;
  // Whether it renders `scene`'s tiles; called once per job, when the job is prepared, on a
  // CPU worker. The scheduler already requires one-pass jobs without AOVs.
  virtual bool accepts(const PreparedScene& scene) const = 0;
  // Renders the beauty pass of `tile` into `rgba` (tile.width * tile.height * 4 floats) as
  // PreparedScene::render_tile does. Throws on failure; the scheduler logs it and renders the
  // tile on the CPU instead.
  virtual TileStats render_tile(const std::shared_ptr<const PreparedScene>& scene,
                                const TileRect& tile, std::span<float> rgba) = 0;
};

}  // namespace tessera::server
