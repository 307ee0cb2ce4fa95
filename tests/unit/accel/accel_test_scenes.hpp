#pragma once
// Scenes and rays for the acceleration-structure tests, and the brute-force reference every
// structure is compared with: tessera::intersect on every triangle, one at a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "tessera/geometry/triangle.hpp"

namespace tessera::accel_test {

inline vec3 random_point(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  return vec3(u(rng), u(rng), u(rng));
}

inline vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (;;) {
    const vec3 d(n(rng), n(rng), n(rng));
    const float len = glm::length(d);
    if (len > 1e-3f) return d / len;
  }
}

// Triangles of random size and orientation in [-1, 1]^3, many overlapping.
inline std::vector<Triangle> triangle_soup(std::uint32_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> size(0.01f, 0.4f);
  std::vector<Triangle> tris;
  for (std::uint32_t i = 0; i < count; ++i) {
    const vec3 c = random_point(rng, -1.0f, 1.0f);
    const float s = size(rng);
    tris.push_back(Triangle{c + s * random_direction(rng), c + s * random_direction(rng),
                            c + s * random_direction(rng), 0});
  }
  return tris;
}

// A closed, watertight mesh: the unit sphere subdivided from an octahedron (8 * 4^levels
// triangles) with shared vertices, centred on the origin.
inline std::vector<Triangle> closed_sphere(int levels) {
  std::vector<Triangle> tris;
  const vec3 axes[6] = {vec3(1, 0, 0),  vec3(-1, 0, 0), vec3(0, 1, 0),
                        vec3(0, -1, 0), vec3(0, 0, 1),  vec3(0, 0, -1)};
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const vec3 a = axes[sx], b = axes[2 + sy], c = axes[4 + sz];
        // Consistent outward winding.
        if (glm::dot(glm::cross(b - a, c - a), a + b + c) > 0.0f)
          tris.push_back(Triangle{a, b, c, 0});
        else
          tris.push_back(Triangle{a, c, b, 0});
      }
  for (int level = 0; level < levels; ++level) {
    std::vector<Triangle> next;
    for (const Triangle& t : tris) {
      // Midpoints normalised identically for both triangles sharing an edge (the sum is
      // symmetric), so shared vertices are bit-identical.
      const vec3 ab = glm::normalize(t.p0 + t.p1), bc = glm::normalize(t.p1 + t.p2),
                 ca = glm::normalize(t.p2 + t.p0);
      next.push_back(Triangle{t.p0, ab, ca, 0});
      next.push_back(Triangle{t.p1, bc, ab, 0});
      next.push_back(Triangle{t.p2, ca, bc, 0});
      next.push_back(Triangle{ab, bc, ca, 0});
    }
    tris = std::move(next);
  }
  return tris;
}

// Axis-aligned unit squares (two triangles each) lying exactly on the planes x = i, y = j
// and z = k of an integer grid: every box of such a triangle is flat, and rays along the
// axes from integer coordinates run exactly along box faces and triangle edges.
inline std::vector<Triangle> axis_aligned_grid(int cells) {
  std::vector<Triangle> tris;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int plane = 0; plane <= cells; plane += 2)
      for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; j += 2) {
          vec3 p00(0.0f), p10(0.0f), p01(0.0f), p11(0.0f);
          for (vec3* p : {&p00, &p10, &p01, &p11}) (*p)[axis] = static_cast<float>(plane);
          p00[u] = p01[u] = static_cast<float>(i);
          p10[u] = p11[u] = static_cast<float>(i + 1);
          p00[v] = p10[v] = static_cast<float>(j);
          p01[v] = p11[v] = static_cast<float>(j + 1);
          tris.push_back(Triangle{p00, p10, p11, 0});
          tris.push_back(Triangle{p00, p11, p01, 0});
        }
  }
  return tris;
}

// Random rays plus the awkward ones: axis-parallel directions with +0.0 and -0.0 in the
// other components, origins on integer planes, and very short and empty t intervals.
inline std::vector<Ray> test_rays(std::uint32_t count, std::uint32_t seed, float extent) {
  std::mt19937 rng(seed);
  std::vector<Ray> rays;
  for (std::uint32_t i = 0; i < count; ++i) {
    const vec3 o = random_point(rng, -extent, extent);
    rays.push_back(Ray{o, random_direction(rng), 0.0f, kInfinity});
  }
  std::uniform_int_distribution<int> cell(-1, static_cast<int>(extent) + 1);
  for (std::uint32_t i = 0; i < count / 2; ++i) {
    const int axis = static_cast<int>(i % 3);
    vec3 d(((i / 3) % 2) ? -0.0f : 0.0f, ((i / 6) % 2) ? -0.0f : 0.0f,
           ((i / 12) % 2) ? -0.0f : 0.0f);
    d[axis] = ((i / 24) % 2) ? -1.0f : 1.0f;
    // Half start on integer coordinates (on box and triangle planes), half anywhere.
    const vec3 o = (i % 2) ? vec3(static_cast<float>(cell(rng)), static_cast<float>(cell(rng)),
                                  static_cast<float>(cell(rng)))
                           : random_point(rng, -extent, extent);
    rays.push_back(Ray{o, d, 0.0f, kInfinity});
  }
  for (std::uint32_t i = 0; i < count / 8; ++i) {
    const vec3 o = random_point(rng, -extent, extent);
    const float t_min = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
    rays.push_back(Ray{o, random_direction(rng), t_min,
                       t_min + std::uniform_real_distribution<float>(0.0f, 1.5f)(rng)});
  }
  return rays;
}

struct ReferenceHit {
  bool hit = false;
  HitRecord record;
};

inline ReferenceHit reference_closest(const std::vector<Triangle>& tris, const Ray& ray) {
  ReferenceHit result;
  result.record.t = ray.t_max;
  for (std::uint32_t i = 0; i < tris.size(); ++i)
    result.hit |= intersect(tris[i], ray, result.record.t, result.record, i);
  return result;
}

// Every hit of the ray, nearest first (ties by triangle index).
inline std::vector<HitRecord> reference_all(const std::vector<Triangle>& tris, const Ray& ray) {
  std::vector<HitRecord> hits;
  for (std::uint32_t i = 0; i < tris.size(); ++i) {
    HitRecord h;
    if (intersect(tris[i], ray, ray.t_max, h, i)) hits.push_back(h);
  }
  std::sort(hits.begin(), hits.end(), [](const HitRecord& a, const HitRecord& b) {
    return a.t < b.t || (a.t == b.t && a.primitive < b.primitive);
  });
  return hits;
}

}  // namespace tessera::accel_test
