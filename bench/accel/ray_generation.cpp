#include "ray_generation.hpp"

#include <algorithm>
#include <cmath>

#include "bench_random.hpp"

namespace tessera::bench {

std::vector<Ray> make_primary_rays(const Aabb& bounds, std::uint32_t width, std::uint32_t height) {
  const vec3 center = bounds.centroid();
  const float radius = 0.5f * glm::length(bounds.extent());
  const vec3 back = glm::normalize(vec3(0.3f, -1.0f, 0.25f));
  const vec3 position = center + back * (2.5f * radius);
  const vec3 forward = -back;
  const vec3 right = glm::normalize(glm::cross(forward, vec3(0.0f, 0.0f, 1.0f)));
  const vec3 up = glm::cross(right, forward);
  // The narrowest field of view that still shows all eight corners of the box.
  float tan_half = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 p((corner & 1) ? bounds.upper.x : bounds.lower.x,
                 (corner & 2) ? bounds.upper.y : bounds.lower.y,
                 (corner & 4) ? bounds.upper.z : bounds.lower.z);
    const vec3 q = p - position;
    const float depth = glm::dot(q, forward);
    tan_half = std::max(
        {tan_half, std::fabs(glm::dot(q, right)) / depth, std::fabs(glm::dot(q, up)) / depth});
  }
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(width) * height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      // The shorter image side spans the field of view.
      const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 1.0f) *
                       tan_half * (aspect >= 1.0f ? aspect : 1.0f);
      const float sy = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(height)) *
                       tan_half / (aspect >= 1.0f ? 1.0f : aspect);
      rays.push_back(
          Ray{position, glm::normalize(forward + sx * right + sy * up), 0.0f, kInfinity});
    }
  }
  return rays;
}

std::vector<Ray> make_diffuse_rays(std::span<const Ray> primary,
                                   std::span<const HitRecord> primary_hits,
                                   std::span<const Triangle> triangles, const Aabb& bounds) {
  const float lift = 1e-5f * 0.5f * glm::length(bounds.extent());
  constexpr std::uint64_t kStream = 0xd1ff05e;
  std::vector<Ray> rays;
  for (std::size_t i = 0; i < primary.size(); ++i) {
    const HitRecord& hit = primary_hits[i];
    if (!hit.valid()) continue;
    const Triangle& tri = triangles[hit.primitive];
    const vec3 p = (1.0f - hit.u - hit.v) * tri.p0 + hit.u * tri.p1 + hit.v * tri.p2;
    vec3 n = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    const float len = glm::length(n);
    if (!(len > 0.0f)) continue;
    n /= len;
    if (glm::dot(n, primary[i].direction) > 0.0f) n = -n;
    // Cosine-weighted hemisphere sample (Malley: uniform disk lifted onto the hemisphere).
    const float u1 = random_unit(kStream, 2 * i), u2 = random_unit(kStream, 2 * i + 1);
    const float r = std::sqrt(u1), phi = 6.28318530717958647692f * u2;
    const float lx = r * std::cos(phi), ly = r * std::sin(phi),
                lz = std::sqrt(std::max(0.0f, 1.0f - u1));
    const Frame frame = Frame::from_normal(n);
    const vec3 d = glm::normalize(frame.to_world(vec3(lx, ly, lz)));
    rays.push_back(Ray{p + lift * n, d, 0.0f, kInfinity});
  }
  return rays;
}

}  // namespace tessera::bench
