#pragma once
// How a job with progressive passes (render.passes > 1) is laid out as store tiles: every
// (tile, pass) is one unit of work with its own store index, pass-major, so that handing
// units out in index order renders pass 1 of every tile, then pass 2, and so on; the store's
// completion order (the tile ordinal) is then the stream's sequence. A one-pass job's units
// are its tiles, with the same indices as before passes existed.
#include <cstdint>

#include "tessera/scene/scene_description.hpp"

namespace tessera::server {

struct TilePass {
  std::uint32_t tile = 0;  // row-major index in the job's tile grid
  std::uint32_t pass = 1;  // 1-based
};

class PassLayout {
 public:
  explicit PassLayout(const RenderSettings& settings);

  std::uint32_t tiles() const { return tiles_; }
  std::uint32_t passes() const { return passes_; }
  // Store tiles of the job: tiles() * passes().
  std::uint32_t units() const { return tiles_ * passes_; }
  std::uint32_t unit(TilePass tile_pass) const {
    return (tile_pass.pass - 1) * tiles_ + tile_pass.tile;
  }
  TilePass of(std::uint32_t unit) const { return {unit % tiles_, unit / tiles_ + 1}; }
  // Samples per pixel done after `pass`.
  std::uint32_t samples_after(std::uint32_t pass) const;

 private:
  std::uint32_t tiles_;
  std::uint32_t passes_;
  std::uint32_t samples_;
};

}  // namespace tessera::server
