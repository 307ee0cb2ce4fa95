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
class TileAssembler {
 public:
  // `exr_path` empty: keep the image in memory only.
  // `channels`: the EXR's channels, R, G, B and A first (see output_channels()).
  TileAssembler(std::uint32_t width, std::uint32_t height, std::uint32_t tile_size,
                const std::optional<std::filesystem::path>& exr_path,
                std::vector<std::string> channels = rgba_channels());
  ~TileAssembler();
  TileAssembler(const TileAssembler&) = delete;
  TileAssembler& operator=(const TileAssembler&) = delete;

  // `pixels` holds tile.width * tile.height pixels of channels().size() floats. Throws
  // std::runtime_error for a tile outside the grid, of the wrong size, or seen before.
  void add_tile(const TileRect& tile, std::span<const float> pixels);
  const std::vector<std::string>& channels() const { return channels_; }

  std::uint32_t tile_size() const { return tile_size_; }
  std::uint32_t tiles_received() const { return received_count_; }
  std::uint32_t tiles_total() const { return static_cast<std::uint32_t>(grid_.size()); }
  bool complete() const { return received_count_ == grid_.size(); }

  // Closes the EXR and rewrites it whole with `metadata` in its header. Throws
  // std::runtime_error naming the first missing tile, if any.
  void finish(const ImageMetadata& metadata = {});
  // Closes the EXR without checking; for giving up on a failed job.
  void abandon();

  // The beauty pass (R, G, B, A) of the tiles received so far, for the preview.
  const RgbaImage& image() const { return image_; }

 private:
  std::uint32_t tile_size_;
  std::vector<std::string> channels_;
  std::vector<TileRect> grid_;
  std::vector<bool> received_;
  std::uint32_t received_count_ = 0;
  RgbaImage image_;
  ChannelImage all_channels_;
  std::optional<std::filesystem::path> exr_path_;
  std::unique_ptr<TiledExrWriter> writer_;
};

}  // namespace tessera
