// gpu::TileRenderer: uploads a job's PreparedScene::device_source to one CUDA device and
// renders tiles with the kernel of the smallest feature set covering the scene
// (path_tracer_kernel.cuh).
#include <cuda_runtime.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "path_tracer_kernel.cuh"
#include "tessera/gpu/gpu_renderer.hpp"

namespace tessera::gpu {

namespace {

// Device memory freed with its owner.
struct DeviceAllocation {
  void* pointer = nullptr;
  DeviceAllocation() = default;
  explicit DeviceAllocation(std::size_t bytes) { check(cudaMalloc(&pointer, bytes), "cudaMalloc"); }
  DeviceAllocation(DeviceAllocation&& other) noexcept : pointer(other.pointer) {
    other.pointer = nullptr;
  }
  DeviceAllocation& operator=(DeviceAllocation&& other) noexcept {
    std::swap(pointer, other.pointer);
    return *this;
  }
  ~DeviceAllocation() {
    if (pointer != nullptr) cudaFree(pointer);
  }
};

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> devices;
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) {
    cudaGetLastError();  // no driver or no device: clear the error, report none
    return devices;
  }
  for (int i = 0; i < count; ++i) {
    cudaDeviceProp prop{};
    if (cudaGetDeviceProperties(&prop, i) != cudaSuccess) continue;
    DeviceInfo info;
    info.index = i;
    info.name = prop.name;
    info.memory_bytes = prop.totalGlobalMem;
    info.compute_major = prop.major;
    info.compute_minor = prop.minor;
    info.multiprocessors = prop.multiProcessorCount;
    devices.push_back(info);
  }
  return devices;
}

struct TileRenderer::State {
  int device = 0;
  std::shared_ptr<const PreparedScene> scene;
  SceneView view;  // device pointers
  std::vector<DeviceAllocation> buffers;
  // Grown to the largest batch so far: the tiles' planes one after another, the
  // tile rectangles and film pointers the kernel reads, and a ray count per tile.
  DeviceAllocation film;
  std::size_t film_bytes = 0;
  DeviceAllocation batch;
  std::size_t batch_tiles = 0;
  std::vector<float> staging;  // the batch's planes on the host, as laid out in `film`
  cudaStream_t stream = nullptr;
  std::size_t uploaded = 0;
};

TileRenderer::TileRenderer(int device, std::shared_ptr<const PreparedScene> scene)
    : state_(std::make_unique<State>()) {
  const DeviceSceneSource& source = scene->device_source();
  if (!source.unsupported.empty()) throw std::invalid_argument(source.unsupported);
  State& s = *state_;
  s.device = device;
  s.scene = std::move(scene);
  check(cudaSetDevice(device), "cudaSetDevice");
  check(cudaStreamCreate(&s.stream), "cudaStreamCreate");
  s.view = source.view;
  for (const DeviceBuffer& b : source.buffers) {
    DeviceAllocation copy(b.bytes);
    check(cudaMemcpy(copy.pointer, b.host, b.bytes, cudaMemcpyHostToDevice), "cudaMemcpy (scene)");
    b.assign(s.view, copy.pointer);
    s.uploaded += b.bytes;
    s.buffers.push_back(std::move(copy));
  }
}

TileRenderer::~TileRenderer() {
  if (state_ && state_->stream != nullptr) cudaStreamDestroy(state_->stream);
}

std::size_t TileRenderer::uploaded_bytes() const {
  return state_->uploaded;
}

// Renders tiles[i] into destinations[i] in one launch. Every plane present is tile-sized
// (pixel_count * 4 floats) and starts as render_tile starts it: depth at +inf, the rest at 0.
std::vector<TileStats> TileRenderer::render_batch(std::span<const TileRect> tiles,
                                                  std::span<const TileDestination> destinations) {
  State& s = *state_;
  if (tiles.empty()) return {};
  if (tiles.size() > 65535)
    throw std::invalid_argument("TileRenderer::render_tiles: more than 65535 tiles in a batch");
  std::size_t floats = 0;
  std::uint32_t largest_width = 0, largest_height = 0;
  bool starts_at_zero = true;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    for (std::size_t p = 0; p < destinations[i].size(); ++p)
      if (destinations[i][p] != nullptr) {
        floats += tiles[i].pixel_count() * 4;
        starts_at_zero = starts_at_zero && (p == 0 || aov_start(p - 1) == 0.0f);
      }
    largest_width = std::max(largest_width, tiles[i].width);
    largest_height = std::max(largest_height, tiles[i].height);
  }
  check(cudaSetDevice(s.device), "cudaSetDevice");
  const std::size_t bytes = floats * sizeof(float);
  if (bytes > s.film_bytes) {
    s.film = DeviceAllocation(bytes);
    s.film_bytes = bytes;
  }
  // The batch's arrays in one allocation: rectangles, then film planes, then ray counts.
  const std::size_t films_at = (tiles.size() * sizeof(TileRect) + 15) / 16 * 16;
  const std::size_t counts_at = (films_at + tiles.size() * sizeof(FilmPlanes) + 7) / 8 * 8;
  const std::size_t batch_bytes = counts_at + tiles.size() * sizeof(unsigned long long);
  if (tiles.size() > s.batch_tiles) {
    s.batch = DeviceAllocation(batch_bytes);
    s.batch_tiles = tiles.size();
  }
  // The planes lie one after another, tile by tile; the staging buffer mirrors the film, so
  // it carries the planes' start values up (when a plane does not start at 0) and the
  // rendered planes down.
  auto* film_base = static_cast<float*>(s.film.pointer);
  s.staging.resize(floats);
  std::vector<unsigned char> arrays(counts_at);
  std::memcpy(arrays.data(), tiles.data(), tiles.size() * sizeof(TileRect));
  std::size_t offset = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    FilmPlanes film;
    const std::size_t plane_floats = tiles[i].pixel_count() * 4;
    for (std::size_t p = 0; p < destinations[i].size(); ++p) {
      if (destinations[i][p] == nullptr) continue;
      (p == 0 ? film.beauty : aov_plane(film, p - 1)) = film_base + offset;
      if (!starts_at_zero)
        std::fill_n(s.staging.begin() + static_cast<std::ptrdiff_t>(offset), plane_floats,
                    p == 0 ? 0.0f : aov_start(p - 1));
      offset += plane_floats;
    }
    std::memcpy(arrays.data() + films_at + i * sizeof(FilmPlanes), &film, sizeof(FilmPlanes));
  }
  auto* batch = static_cast<unsigned char*>(s.batch.pointer);
  if (starts_at_zero)
    check(cudaMemsetAsync(s.film.pointer, 0, bytes, s.stream), "cudaMemsetAsync (film)");
  else
    check(
        cudaMemcpyAsync(s.film.pointer, s.staging.data(), bytes, cudaMemcpyHostToDevice, s.stream),
        "cudaMemcpyAsync (film start)");
  check(cudaMemsetAsync(batch + counts_at, 0, tiles.size() * sizeof(unsigned long long), s.stream),
        "cudaMemsetAsync (ray counts)");
  check(cudaMemcpyAsync(batch, arrays.data(), arrays.size(), cudaMemcpyHostToDevice, s.stream),
        "cudaMemcpyAsync (tiles)");
  const RenderSettings& r = s.scene->settings();
  const PixelSampling sampling = pixel_sampling(r, FilmPlanes{});
  const auto launch = (s.scene->required_features().shapes & ~kCommonShapes) == 0
                          ? &cuda::launch_path_tracer_tiles<cuda::kDeviceCommonShapes>
                          : &cuda::launch_path_tracer_tiles<cuda::kDeviceAllShapes>;
  auto* counts = reinterpret_cast<unsigned long long*>(batch + counts_at);
  check(launch(s.view, r.seed, sampling, r.max_depth, r.sampler, r.light_strategy,
               static_cast<float>(r.clamp), r.transparent_background,
               reinterpret_cast<const TileRect*>(batch),
               reinterpret_cast<const FilmPlanes*>(batch + films_at),
               static_cast<std::uint32_t>(tiles.size()), largest_width, largest_height, counts,
               s.stream),
        "kernel launch");
  std::vector<unsigned long long> rays(tiles.size());
  check(cudaMemcpyAsync(s.staging.data(), s.film.pointer, bytes, cudaMemcpyDeviceToHost, s.stream),
        "cudaMemcpyAsync (film)");
  check(cudaMemcpyAsync(rays.data(), counts, rays.size() * sizeof(unsigned long long),
                        cudaMemcpyDeviceToHost, s.stream),
        "cudaMemcpyAsync (ray counts)");
  check(cudaStreamSynchronize(s.stream), "tile render");
  std::vector<TileStats> stats(tiles.size());
  offset = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const std::size_t plane_floats = tiles[i].pixel_count() * 4;
    for (float* to : destinations[i]) {
      if (to == nullptr) continue;
      std::copy_n(s.staging.begin() + static_cast<std::ptrdiff_t>(offset), plane_floats, to);
      offset += plane_floats;
    }
    stats[i].rays = rays[i];
  }
  return stats;
}

TileStats TileRenderer::render_tile(const TileRect& tile, std::span<float> rgba) {
  const std::span<float> planes[] = {rgba};
  return render_tiles(std::span(&tile, 1), planes)[0];
}

std::vector<TileStats> TileRenderer::render_tiles(std::span<const TileRect> tiles,
                                                  std::span<const std::span<float>> rgba) {
  if (tiles.size() != rgba.size())
    throw std::invalid_argument("TileRenderer::render_tiles: a buffer per tile");
  std::vector<TileDestination> destinations(tiles.size());
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    if (rgba[i].size() != tiles[i].pixel_count() * 4)
      throw std::invalid_argument("TileRenderer::render_tiles: a buffer does not hold its tile");
    destinations[i].fill(nullptr);
    destinations[i][0] = rgba[i].data();
  }
  return render_batch(tiles, destinations);
}

TileStats TileRenderer::render_tile(const TileRect& tile, TilePasses& passes) {
  return render_tiles(std::span(&tile, 1), std::span(&passes, 1))[0];
}

std::vector<TileStats> TileRenderer::render_tiles(std::span<const TileRect> tiles,
                                                  std::span<TilePasses> passes) {
  if (tiles.size() != passes.size())
    throw std::invalid_argument("TileRenderer::render_tiles: passes per tile");
  std::vector<TileDestination> destinations(tiles.size());
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    FilmPlanes host = state_->scene->film_for(tiles[i], passes[i], 0);
    destinations[i][0] = host.beauty;
    for (std::size_t a = 0; a < kAovCount; ++a) destinations[i][1 + a] = aov_plane(host, a);
  }
  return render_batch(tiles, destinations);
}

}  // namespace tessera::gpu
