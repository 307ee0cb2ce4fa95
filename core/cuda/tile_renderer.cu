// gpu::TileRenderer: uploads a job's PreparedScene::device_source to one CUDA device and
// renders tiles with the kernel of the smallest feature set covering the scene
// (path_tracer_kernel.cuh).
#include <cuda_runtime.h>

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
  DeviceAllocation film;  // beauty plane of the largest tile rendered so far
  std::size_t film_bytes = 0;
  DeviceAllocation ray_count;
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
  s.ray_count = DeviceAllocation(sizeof(unsigned long long));
}

TileRenderer::~TileRenderer() {
  if (state_ && state_->stream != nullptr) cudaStreamDestroy(state_->stream);
}

std::size_t TileRenderer::uploaded_bytes() const {
  return state_->uploaded;
}

TileStats TileRenderer::render_tile(const TileRect& tile, std::span<float> rgba) {
  State& s = *state_;
  const std::size_t bytes = tile.pixel_count() * 4 * sizeof(float);
  if (rgba.size() * sizeof(float) != bytes)
    throw std::invalid_argument("TileRenderer::render_tile: the buffer does not hold the tile");
  check(cudaSetDevice(s.device), "cudaSetDevice");
  if (bytes > s.film_bytes) {
    s.film = DeviceAllocation(bytes);
    s.film_bytes = bytes;
  }
  check(cudaMemsetAsync(s.film.pointer, 0, bytes, s.stream), "cudaMemsetAsync (film)");
  check(cudaMemsetAsync(s.ray_count.pointer, 0, sizeof(unsigned long long), s.stream),
        "cudaMemsetAsync (ray count)");
  const RenderSettings& r = s.scene->settings();
  FilmPlanes film;
  film.beauty = static_cast<float*>(s.film.pointer);
  const PixelSampling sampling = pixel_sampling(r, film);
  const auto launch = (s.scene->required_features().shapes & ~kCommonShapes) == 0
                          ? &cuda::launch_path_tracer_tile<cuda::kDeviceCommonShapes>
                          : &cuda::launch_path_tracer_tile<cuda::kDeviceAllShapes>;
  check(launch(s.view, r.seed, sampling, r.max_depth, r.sampler, r.light_strategy,
               static_cast<float>(r.clamp), r.transparent_background, tile, film,
               static_cast<unsigned long long*>(s.ray_count.pointer), s.stream),
        "kernel launch");
  unsigned long long rays = 0;
  check(cudaMemcpyAsync(rgba.data(), s.film.pointer, bytes, cudaMemcpyDeviceToHost, s.stream),
        "cudaMemcpyAsync (film)");
  check(cudaMemcpyAsync(&rays, s.ray_count.pointer, sizeof(rays), cudaMemcpyDeviceToHost, s.stream),
        "cudaMemcpyAsync (ray count)");
  check(cudaStreamSynchronize(s.stream), "tile render");
  TileStats stats;
  stats.rays = rays;
  return stats;
}

}  // namespace tessera::gpu
