#pragma once
// A device beside the CPU threads that renders whole tiles: a GPU (server/gpu_tile_device.hpp)
// or, in tests, a stand-in. The scheduler gives each device a worker thread of its own that
// takes tiles from the same queue as the CPU workers, so a faster device simply takes more of
// them. A per-tile virtual call: nothing here runs per ray.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera::server {

class TileDevice {
 public:
  virtual ~TileDevice() = default;
  // How logs and metrics name it ("gpu0 NVIDIA H100 80GB HBM3").
  virtual std::string name() const = 0;
  // Whether it renders `scene`'s tiles; called once per job, when the job is prepared, on a
  // CPU worker. The scheduler already requires one-pass jobs.
  virtual bool accepts(const PreparedScene& scene) const = 0;
  // Renders `tile` into `passes` as PreparedScene::render_tile(tile, passes) does: the beauty
  // and each AOV plane the job asks for, sized to the tile, the others emptied. Throws on
  // failure; the scheduler logs it and renders the tile on the CPU instead.
  virtual TileStats render_tile(const std::shared_ptr<const PreparedScene>& scene,
                                const TileRect& tile, TilePasses& passes) = 0;
  // The pixels it renders well in one call. A GPU needs hundreds of thousands of threads in
  // flight, where one tile of a job (16 x 16 by default) gives it 256: the scheduler then
  // hands it consecutive tiles of a job up to this many pixels at once (at least one), for
  // render_tiles. 0: one tile at a time.
  virtual std::size_t batch_pixels() const { return 0; }
  // Renders tiles[i] into passes[i] as render_tile does, all of one job, and returns each
  // tile's stats: how the scheduler calls every device, a single tile being a batch of one.
  // By default one after the other. Throws on failure (the scheduler renders
  // the batch on the CPU instead).
  virtual std::vector<TileStats> render_tiles(const std::shared_ptr<const PreparedScene>& scene,
                                              std::span<const TileRect> tiles,
                                              std::span<TilePasses> passes) {
    std::vector<TileStats> stats;
    for (std::size_t i = 0; i < tiles.size(); ++i)
      stats.push_back(render_tile(scene, tiles[i], passes[i]));
    return stats;
  }
};

}  // namespace tessera::server
