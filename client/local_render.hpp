#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

struct LocalRenderResult {
  std::uint64_t rays = 0;
  double seconds = 0.0;
  bool stopped = false;  // `stop` was raised before every tile was rendered
};

// Called once per finished tile, one call at a time (under a lock), from a worker thread.
// `rgba` holds the tile in output_channels(aovs) layout: R, G, B, A, then any AOVs.
using LocalTileCallback =
    std::function<void(const TileRect& tile, std::span<const float> rgba, std::uint64_t rays)>;

// Renders every tile of the scene in-process on `threads` worker threads (0: all hardware
// threads), tiles handed out in row-major order. Pixels depend only on the scene and the
// pixel, so the image equals render_image()'s whatever the thread count. Workers stop taking
// tiles when `stop` becomes true. An exception from a worker or the callback stops the others
// and is rethrown here.
LocalRenderResult render_local(const PreparedScene& scene, unsigned threads,
                               const LocalTileCallback& on_tile,
                               const std::atomic<bool>* stop = nullptr);

}  // namespace tessera
