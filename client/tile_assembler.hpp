#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tessera/image/exr.hpp"
#include "tessera/render/tile.hpp"

namespace tessera {

// Puts finished tiles together, in whatever order they arrive: each tile is written to the
// tiled EXR at once (so a long render leaves a usable partial file) and copied into the whole
// image, which finish() writes again with the complete header (render time and all: an
// OpenEXR header cannot change once the first tile is written). Checks that every tile matches the
// job's tile grid and arrives exactly once, because the output is only right if the stream was.
//
// A job with progressive passes sends every tile once per pass, each pass of a tile after
// the one before (checked). The image holds each tile's latest pass, and each time every
// tile has reached a pass the EXR is rewritten whole (beside, then renamed over the old
// one), so the file on disk is always a complete image of the last finished pass; a tiled
// EXR cannot take a tile twice, so no tiled writer is used then.
class TileAssembler {
 public:
  // `exr_path` empty: keep the image in memory only.
  // `channels`: the EXR's channels, R, G, B and A first (see output_channels()).
  // `passes`: the job's progressive passes (0 or 1: one).
  TileAssembler(std::uint32_t width, std::uint32_t height, std::uint32_t tile_size,
                const std::optional<std::filesystem::path>& exr_path,
                std::vector<std::string> channels = rgba_channels(), std::uint32_t passes = 1);
  ~TileAssembler();
  TileAssembler(const TileAssembler&) = delete;
  TileAssembler& operator=(const TileAssembler&) = delete;

  // `pixels` holds tile.width * tile.height pixels of channels().size() floats: the tile
  // after pass `pass` (1-based). Throws std::runtime_error for a tile outside the grid, of
  // the wrong size, seen before, or a pass not following the tile's last. Returns true
  // when this tile completed a pass of the whole image (every tile has reached `pass`).
  bool add_tile(const TileRect& tile, std::span<const float> pixels, std::uint32_t pass = 1);
  const std::vector<std::string>& channels() const { return channels_; }

  std::uint32_t tile_size() const { return tile_size_; }
  std::uint32_t tiles_received() const { return received_count_; }
  std::uint32_t tiles_total() const { return static_cast<std::uint32_t>(grid_.size()); }
  bool complete() const { return received_count_ == grid_.size(); }
  std::uint32_t passes() const { return passes_; }
  // Passes every tile has reached.
  std::uint32_t passes_done() const { return passes_done_; }

  // Closes the EXR and rewrites it whole with `metadata` in its header. Throws
  // std::runtime_error naming the first missing tile, if any.
  void finish(const ImageMetadata& metadata = {});
  // Closes the EXR and rewrites it whole with the tiles received so far (the missing ones
  // black with alpha 0): what `--keep-partial` keeps of an interrupted render.
  void finish_partial(const ImageMetadata& metadata = {});
  // Closes the EXR without checking; for giving up on a failed job.
  void abandon();

  // The beauty pass (R, G, B, A) of the tiles received so far, for the preview.
  const RgbaImage& image() const { return image_; }

 private:
  std::uint32_t tile_size_;
  std::vector<std::string> channels_;
  std::vector<TileRect> grid_;
  std::vector<bool> received_;  // the tile's last pass has arrived
  std::uint32_t received_count_ = 0;
  std::uint32_t passes_;
  std::vector<std::uint32_t> tile_passes_;    // per tile: passes received
  std::vector<std::uint32_t> tiles_at_pass_;  // per pass - 1: tiles that reached it
  std::uint32_t passes_done_ = 0;
  RgbaImage image_;
  ChannelImage all_channels_;
  std::optional<std::filesystem::path> exr_path_;
  std::unique_ptr<TiledExrWriter> writer_;  // one-pass jobs only

  void write_whole(const ImageMetadata& metadata);
};

}  // namespace tessera
