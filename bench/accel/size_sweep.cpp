#include "size_sweep.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "bench_random.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "trace_runner.hpp"

namespace tessera::bench {
namespace {

vec3 random_in_cube(std::uint64_t stream, std::uint64_t index) {
  return vec3(2.0f * random_unit(stream, 3 * index) - 1.0f,
              2.0f * random_unit(stream, 3 * index + 1) - 1.0f,
              2.0f * random_unit(stream, 3 * index + 2) - 1.0f);
}

// Triangles of edge about 2 / cbrt(n) scattered in [-1, 1]^3, so they fill the cube at
// every size.
std::vector<Triangle> soup(std::uint32_t count) {
  const float size = 1.5f / std::cbrt(static_cast<float>(count));
  std::vector<Triangle> tris;
  for (std::uint32_t i = 0; i < count; ++i) {
    const vec3 c = random_in_cube(11, i);
    tris.push_back(Triangle{c + size * random_in_cube(12, i), c + size * random_in_cube(13, i),
                            c + size * random_in_cube(14, i), 0});
  }
  return tris;
}

std::vector<Ray> rays_into_cube(std::uint32_t count) {
  std::vector<Ray> rays;
  for (std::uint32_t i = 0; i < count; ++i) {
    const vec3 from = glm::normalize(random_in_cube(21, i) + vec3(1e-3f)) * 3.0f;
    const vec3 to = 0.8f * random_in_cube(22, i);
    rays.push_back(Ray{from, glm::normalize(to - from), 0.0f, kInfinity});
  }
  return rays;
}

}  // namespace

void run_size_sweep(const std::vector<std::uint32_t>& sizes, std::uint32_t ray_count,
                    unsigned repeat) {
  const std::vector<Ray> rays = rays_into_cube(ray_count);
  const AccelKind kinds[] = {AccelKind::kBrute, AccelKind::kBvh, AccelKind::kWide,
                             AccelKind::kOctree};
  std::printf("%10s %12s %12s %12s %12s   (Mrays/s, 1 thread, closest hit; auto picks)\n",
              "triangles", "brute", "bvh", "wide", "octree");
  for (std::uint32_t size : sizes) {
    const std::vector<Triangle> tris = soup(size);
    std::printf("%10u", size);
    for (AccelKind kind : kinds) {
      AccelBuildOptions options;
      options.kind = kind;
      const TriangleAccel accel = TriangleAccel::build(tris, options);
      const TraceTiming timing =
          run_trace(rays.size(), 1, repeat, [&](std::size_t begin, std::size_t end, float* t) {
            for (std::size_t i = begin; i < end; ++i) {
              HitRecord hit;
              t[i - begin] = accel.closest(rays[i], hit) ? hit.t : kInfinity;
            }
          });
      std::printf(" %12.2f", static_cast<double>(rays.size()) / timing.best_cpu_seconds * 1e-6);
    }
    std::printf("   %s\n", std::string(accel_kind_name(choose_accel_kind(size))).c_str());
  }
}

}  // namespace tessera::bench
