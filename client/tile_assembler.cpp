#include "client/tile_assembler.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tessera {

namespace {

std::string describe(const TileRect& t) {
  return "tile " + std::to_string(t.index) + " (" + std::to_string(t.width) + "x" +
         std::to_string(t.height) + " at " + std::to_string(t.x) + "," + std::to_string(t.y) + ")";
}

}  // namespace

TileAssembler::TileAssembler(std::uint32_t width, std::uint32_t height, std::uint32_t tile_size,
                             const std::optional<std::filesystem::path>& exr_path,
                             std::vector<std::string> channels, std::uint32_t passes)
    : tile_size_(tile_size),
      channels_(std::move(channels)),
      grid_(make_tiles(width, height, tile_size)),
      received_(grid_.size(), false),
      passes_(std::max(passes, 1u)),
      tile_passes_(grid_.size(), 0),
      tiles_at_pass_(passes_, 0) {
  if (grid_.empty())
    throw std::invalid_argument("image of " + std::to_string(width) + "x" + std::to_string(height) +
                                " with tile size " + std::to_string(tile_size) + " has no tiles");
  if (channels_.size() < 4 || channels_[0] != "R" || channels_[3] != "A")
    throw std::invalid_argument("output channels must start with R, G, B, A");
  image_.width = width;
  image_.height = height;
  image_.pixels.assign(static_cast<std::size_t>(width) * height * 4, 0.0f);
  exr_path_ = exr_path;
  if (exr_path) {
    all_channels_.width = width;
    all_channels_.height = height;
    all_channels_.channels = channels_;
    all_channels_.pixels.assign(static_cast<std::size_t>(width) * height * channels_.size(), 0.0f);
  }
  if (exr_path && passes_ == 1)
    writer_ = std::make_unique<TiledExrWriter>(*exr_path, width, height, tile_size, channels_);
}

TileAssembler::~TileAssembler() = default;

bool TileAssembler::add_tile(const TileRect& tile, std::span<const float> pixels,
                             std::uint32_t pass) {
  const std::size_t stride = channels_.size();
  if (tile.index >= grid_.size())
    throw std::runtime_error("received " + describe(tile) + " but the image has " +
                             std::to_string(grid_.size()) + " tiles");
  const TileRect& expected = grid_[tile.index];
  if (tile.x != expected.x || tile.y != expected.y || tile.width != expected.width ||
      tile.height != expected.height)
    throw std::runtime_error("received " + describe(tile) + " but the tile grid has " +
                             describe(expected));
  if (pixels.size() != tile.pixel_count() * stride)
    throw std::runtime_error("received " + describe(tile) + " with " +
                             std::to_string(pixels.size() / stride) + " pixels instead of " +
                             std::to_string(tile.pixel_count()));
  if (received_[tile.index]) throw std::runtime_error("received " + describe(tile) + " twice");
  if (pass != tile_passes_[tile.index] + 1 || pass > passes_)
    throw std::runtime_error("received pass " + std::to_string(pass) + " of " + describe(tile) +
                             " after its pass " + std::to_string(tile_passes_[tile.index]) +
                             " (the job has " + std::to_string(passes_) + ")");
  tile_passes_[tile.index] = pass;
  if (pass == passes_) {
    received_[tile.index] = true;
    ++received_count_;
  }
  for (std::uint32_t row = 0; row < tile.height; ++row)
    for (std::uint32_t col = 0; col < tile.width; ++col)
      std::copy_n(
          pixels.begin() + static_cast<std::ptrdiff_t>((row * tile.width + col) * stride), 4,
          image_.pixels.begin() +
              (static_cast<std::ptrdiff_t>(tile.y + row) * image_.width + tile.x + col) * 4);
  if (writer_) writer_->write_tile(tile, pixels);
  if (exr_path_) {
    const std::size_t row_floats = tile.width * stride;
    for (std::uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(
          pixels.begin() + static_cast<std::ptrdiff_t>(row * row_floats), row_floats,
          all_channels_.pixels.begin() +
              static_cast<std::ptrdiff_t>(
                  ((static_cast<std::size_t>(tile.y) + row) * image_.width + tile.x) * stride));
  }
  if (++tiles_at_pass_[pass - 1] < grid_.size()) return false;
  passes_done_ = pass;
  // The last pass's file is written by finish(), with the header.
  if (exr_path_ && pass < passes_) write_whole({});
  return true;
}

void TileAssembler::write_whole(const ImageMetadata& metadata) {
  // Written beside the file and renamed over it, so a failure leaves that intact.
  std::filesystem::path complete = *exr_path_;
  complete += ".tmp.exr";
  write_exr(complete, all_channels_, tile_size_, metadata);
  std::filesystem::rename(complete, *exr_path_);
}

void TileAssembler::finish(const ImageMetadata& metadata) {
  const auto missing = std::find(received_.begin(), received_.end(), false);
  if (missing != received_.end())
    throw std::runtime_error("the stream ended without " +
                             describe(grid_[missing - received_.begin()]) + " (" +
                             std::to_string(received_count_) + " of " +
                             std::to_string(grid_.size()) + " tiles received)");
  if (!exr_path_) return;
  if (writer_) {
    writer_->close();
    writer_.reset();
  }
  write_whole(metadata);
}

void TileAssembler::finish_partial(const ImageMetadata& metadata) {
  if (!exr_path_) return;
  // The tiled file lacks tiles and is replaced whole: a failure to close it changes nothing.
  abandon();
  writer_.reset();
  write_whole(metadata);
}

void TileAssembler::abandon() {
  if (!writer_) return;
  try {
    writer_->close();
  } catch (const std::exception&) {
    // The file is being given up on; a failure to finish it changes nothing.
  }
}

}  // namespace tessera
