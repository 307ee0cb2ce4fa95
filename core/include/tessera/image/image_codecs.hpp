#pragma once
// Image files are read and written through OpenImageIO, which Debian builds against about
// 260 shared libraries (OpenVDB, GDAL, FFmpeg, DICOM, ...). Linked into every program, the
// dynamic linker bound their symbols at every start: `tessera --help` took 0.4 s, 1.1 G of
// its 1.2 G instructions in symbol lookup, and so did each of the test binaries' ~1,300
// processes. The code that calls OpenImageIO is therefore a module of its own,
// libtessera_image_codecs.so (core/image_codecs/), which the functions of image/exr.hpp and
// image/rgb_image.hpp load with dlopen the first time one of them runs. That load is still
// about 0.45 s (0.47 s of a 64x48 one-sample `tessera render --local`). Loading it on a
// thread of its own while the CLI renders, and opening the tiled EXR once it was done, was
// tried (6 December) and gave nothing: the load is CPU work that competes with the render
// threads, which already use every core, and a short render waits for it at the end anyway.
//
// The module is at $TESSERA_IMAGE_CODECS when that is set (and nowhere else then);
// otherwise the first usable one of:
//  1. lib/tessera/ beside the program's bin/ (an installed program: /usr/local/bin and
//     /usr/local/lib/tessera, as the Docker image has them);
//  2. beside the program itself;
//  3. where this build put it (the build tree, for tests and bench tools);
//  4. the install prefix this build was configured with.
// A module whose tag (kAbi: the library's version and the compiler) differs from the
// program's is skipped, so an install of another version never serves this build; two
// builds of one version by one compiler are not told apart, which the search order above
// covers (a program finds its own build's or its own prefix's module first).
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "tessera/image/exr.hpp"
#include "tessera/image/rgb_image.hpp"

namespace tessera {

// Loads the image codecs now if they are not loaded yet, and returns the module's path.
// Throws std::runtime_error naming every place looked in when none holds a usable module.
// tesserad calls it at start, so that a daemon unable to write images refuses to start
// instead of failing its first job.
std::filesystem::path load_image_codecs();

namespace image_codecs {

// Both sides come from one source tree and one compiler, so the table passes the library's
// own types; the tag below is compared before any of them is used.
inline constexpr char kAbi[] = "tessera-image-codecs/1 " TESSERA_VERSION " " __VERSION__;

// The module's one exported symbol: `extern "C" const Table* tessera_image_codecs_table()`.
inline constexpr char kEntryPoint[] = "tessera_image_codecs_table";

struct Table;
using EntryPointFunction = const Table* (*)();

struct Table {
  const char* abi;  // kAbi as the module was compiled
  std::vector<std::uint8_t> (*encode_exr)(std::span<const float> pixels, std::uint32_t width,
                                          std::uint32_t height,
                                          const std::vector<std::string>& channels, std::uint32_t x,
                                          std::uint32_t y);
  ChannelImage (*decode_exr_channels)(std::span<const std::uint8_t> bytes);
  RgbaImage (*decode_exr)(std::span<const std::uint8_t> bytes);
  // A tiled EXR open for writing: an opaque handle for the three functions after it.
  void* (*open_tiled_exr)(const std::filesystem::path& path, std::uint32_t width,
                          std::uint32_t height, std::uint32_t tile_size,
                          const std::vector<std::string>& channels, const ImageMetadata& metadata);
  void (*write_tile)(void* file, const TileRect& tile, std::span<const float> pixels);
  void (*close_tiled_exr)(void* file);  // finishes the file; throws when that fails
  void (*free_tiled_exr)(void* file);   // never throws
  void (*write_exr)(const std::filesystem::path& path, const ChannelImage& image,
                    std::uint32_t tile_size, const ImageMetadata& metadata);
  void (*write_rgba_exr)(const std::filesystem::path& path, const RgbaImage& image);
  // Eight-bit RGB, already tone-mapped and encoded, to any format OpenImageIO writes.
  void (*write_rgb8)(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                     std::span<const std::uint8_t> rgb);
  ImageHeader (*read_header)(const std::filesystem::path& path);
  RgbaImage (*read_rgba)(const std::filesystem::path& path);
  RgbImage (*read_rgb)(const std::filesystem::path& path, std::uint64_t max_pixels);
};

// The loaded table (load_image_codecs' module); throws as it does.
const Table& table();

// The places looked in, in order (see above); those given by nothing are left out.
std::vector<std::filesystem::path> candidate_paths();

// Opens the first usable module of `candidates` without keeping it as the process's
// codecs; nullptr, with `error` saying what was wrong with each, when none is usable.
// For the loader and its tests.
const Table* open_first(const std::vector<std::filesystem::path>& candidates,
                        std::filesystem::path& opened, std::string& error);

}  // namespace image_codecs
}  // namespace tessera
