// gpu::TileRenderer: uploads a job's PreparedScene::device_source to one CUDA device and
// renders tiles with the kernel of the smallest feature set covering the scene
// (path_tracer_kernel.cuh).
#include <cuda_runtime.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "path_tracer_kernel.cuh"
#include "tessera/gpu/gpu_renderer.hpp"

namespace tessera::gpu {

namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess)
    throw std::runtime_error(std::string("CUDA ") + what + ": " + cudaGetErrorString(status));
}

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
  // Grown to the largest batch so far: the tiles' beauty planes one after another, the
  // tile rectangles and film pointers the kernel reads, and a ray count per tile.
  DeviceAllocation film;
  std::size_t film_bytes = 0;
  DeviceAllocation batch;
  std::size_t batch_tiles = 0;
  std::vector<float> staging;  // the batch's beauty planes on the host
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

TileStats TileRenderer::render_tile(const TileRect& tile, std::span<float> rgba) {
  const std::span<float> planes[] = {rgba};
  return render_tiles(std::span(&tile, 1), planes)[0];
}

std::vector<TileStats> TileRenderer::render_tiles(std::span<const TileRect> tiles,
                                                  std::span<const std::span<float>> rgba) {
  State& s = *state_;
  if (tiles.size() != rgba.size())
    throw std::invalid_argument("TileRenderer::render_tiles: a buffer per tile");
  if (tiles.empty()) return {};
  if (tiles.size() > 65535)
    throw std::invalid_argument("TileRenderer::render_tiles: more than 65535 tiles in a batch");
  std::size_t floats = 0;
  std::uint32_t largest_width = 0, largest_height = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    if (rgba[i].size() != tiles[i].pixel_count() * 4)
      throw std::invalid_argument("TileRenderer::render_tiles: a buffer does not hold its tile");
    floats += rgba[i].size();
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
  auto* film_base = static_cast<float*>(s.film.pointer);
  std::vector<unsigned char> arrays(counts_at);
  std::memcpy(arrays.data(), tiles.data(), films_at);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    FilmPlanes film;
    film.beauty = film_base + offset;
    offset += rgba[i].size();
    std::memcpy(arrays.data() + films_at + i * sizeof(FilmPlanes), &film, sizeof(FilmPlanes));
  }
  auto* batch = static_cast<unsigned char*>(s.batch.pointer);
  check(cudaMemsetAsync(s.film.pointer, 0, bytes, s.stream), "cudaMemsetAsync (film)");
  check(cudaMemsetAsync(batch + counts_at, 0, tiles.size() * sizeof(unsigned long long), s.stream),
        "cudaMemsetAsync (ray counts)");
  check(cudaMemcpyAsync(batch, arrays.data(), arrays.size(), cudaMemcpyHostToDevice, s.stream),
        "cudaMemcpyAsync (tiles)");
  const RenderSettings& r = s.scene->settings();
  FilmPlanes first;
  first.beauty = film_base;
  const PixelSampling sampling = pixel_sampling(r, first);
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
  s.staging.resize(floats);
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
    std::copy_n(s.staging.begin() + static_cast<std::ptrdiff_t>(offset), rgba[i].size(),
                rgba[i].begin());
    offset += rgba[i].size();
    stats[i].rays = rays[i];
  }
  return stats;
}

}  // namespace tessera::gpu
