#include "client/local_render.hpp"

#include "tessera/render/output_channels.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace tessera {

LocalRenderResult render_local(const PreparedScene& scene, unsigned threads,
                               const LocalTileCallback& on_tile, const std::atomic<bool>* stop) {
  const auto start = std::chrono::steady_clock::now();
  const RenderSettings& s = scene.settings();
  const std::vector<TileRect> tiles = make_tiles(s.width, s.height, s.tile_size);
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads =
      static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(tiles.size(), 1)));

  std::atomic<std::size_t> next_tile{0};
  std::atomic<bool> failed{false};
  std::mutex callback_mutex;
  std::exception_ptr error;
  std::uint64_t rays = 0;
  std::size_t tiles_done = 0;

  const auto worker = [&] {
    TilePasses passes;
    std::vector<float> interleaved;
    const std::uint32_t aovs = scene.settings().aovs;
    try {
      while (!failed.load(std::memory_order_relaxed) &&
             !(stop && stop->load(std::memory_order_relaxed))) {
        const std::size_t i = next_tile.fetch_add(1, std::memory_order_relaxed);
        if (i >= tiles.size()) break;
        const TileStats stats = scene.render_tile(tiles[i], passes);
        if (aovs != 0) interleaved = interleave_passes(passes, aovs);
        const std::vector<float>& pixels = aovs != 0 ? interleaved : passes.beauty;
        std::lock_guard lock(callback_mutex);
        rays += stats.rays;
        ++tiles_done;
        if (on_tile) on_tile(tiles[i], pixels, stats.rays);
      }
    } catch (...) {
      std::lock_guard lock(callback_mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };

  std::vector<std::thread> workers;
  workers.reserve(threads);
  for (unsigned t = 0; t < threads; ++t) workers.emplace_back(worker);
  for (std::thread& t : workers) t.join();
  if (error) std::rethrow_exception(error);

  LocalRenderResult result;
  result.rays = rays;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.stopped = tiles_done < tiles.size();
  return result;
}

}  // namespace tessera
