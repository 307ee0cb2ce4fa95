#include "gpu_trace.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

#include "mesh_files.hpp"
#include "ray_file.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "tessera/gpu/gpu_renderer.hpp"
#include "tessera/gpu/mesh_ray_tracer.hpp"
#include "trace_runner.hpp"

namespace tessera::bench {

int run_gpu_trace(const std::string& mesh_path, const std::string& rays_path, unsigned threads,
                  unsigned repeat, int device) {
  const std::vector<gpu::DeviceInfo> devices = gpu::list_devices();
  if (device < 0 || static_cast<std::size_t>(device) >= devices.size()) {
    std::fprintf(stderr, "tessera-bench: no CUDA device %d (%zu found)\n", device, devices.size());
    return 1;
  }
  const std::vector<Triangle> triangles = to_triangles(load_mesh_with_assimp(mesh_path));
  const std::vector<Ray> rays = read_ray_file(rays_path);
  std::printf("mesh: %s, %zu triangles; rays: %zu; device %d: %s, %d SMs\n", mesh_path.c_str(),
              triangles.size(), rays.size(), device, devices[device].name.c_str(),
              devices[device].multiprocessors);

  const TriangleAccel accel = TriangleAccel::build(triangles);
  std::vector<float> cpu_t;
  const TraceTiming cpu = run_trace(
      rays.size(), threads, repeat,
      [&](std::size_t begin, std::size_t end, float* t) {
        for (std::size_t i = begin; i < end; ++i) {
          HitRecord hit;
          t[i - begin] = accel.closest(rays[i], hit) ? hit.t : kInfinity;
        }
      },
      &cpu_t);
  std::printf("cpu (%u threads, %s kernels): %.1f Mrays/s, hits=%llu\n", threads,
              std::string(accel.stats().isa).c_str(), cpu.mrays_per_s,
              static_cast<unsigned long long>(cpu.hits));

  gpu::MeshRayTracer tracer(device, triangles);
  double gpu_mrays[2] = {0.0, 0.0};
  for (const gpu::DeviceWalk walk : {gpu::DeviceWalk::kCompressed, gpu::DeviceWalk::kBinary}) {
    const gpu::DeviceTraceResult result = tracer.trace(rays, walk, repeat);
    std::size_t hits = 0, disagree = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool gpu_hit = std::isfinite(result.t[i]), cpu_hit = std::isfinite(cpu_t[i]);
      hits += gpu_hit ? 1 : 0;
      if (gpu_hit != cpu_hit) {
        ++disagree;
      } else if (gpu_hit) {
        const double relative = std::fabs(static_cast<double>(result.t[i]) - cpu_t[i]) /
                                std::max(1e-30, std::fabs(static_cast<double>(cpu_t[i])));
        worst = std::max(worst, relative);
      }
    }
    const double mrays = static_cast<double>(rays.size()) / result.best_seconds * 1e-6;
    gpu_mrays[walk == gpu::DeviceWalk::kCompressed ? 0 : 1] = mrays;
    std::printf(
        "gpu %s walk: %.1f Mrays/s (best of %u kernel runs), hits=%zu, %zu rays hit on "
        "one side only, largest relative t difference %.2e\n",
        walk == gpu::DeviceWalk::kCompressed ? "compressed" : "binary", mrays, repeat, hits,
        disagree, worst);
  }
  std::printf(
      "gpu_compressed_mrays_per_s=%.1f gpu_binary_mrays_per_s=%.1f cpu_mrays_per_s=%.1f "
      "gpu_over_cpu=%.2f uploaded_mb=%.1f\n",
      gpu_mrays[0], gpu_mrays[1], cpu.mrays_per_s, gpu_mrays[0] / cpu.mrays_per_s,
      static_cast<double>(tracer.uploaded_bytes()) / 1e6);
  return 0;
}

}  // namespace tessera::bench
