#include "synthetic_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "bench_random.hpp"

namespace tessera::bench {
namespace {

vec3 knot_curve(float s) {
  constexpr float p = 3.0f, q = 7.0f;
  const float r = std::cos(q * s) + 2.0f;
  return vec3(r * std::cos(p * s), r * std::sin(p * s), -std::sin(q * s));
}

IndexedMesh make_knot(std::size_t min_triangles) {
  constexpr std::uint32_t ring = 96;  // vertices around the tube
  const auto segments = static_cast<std::uint32_t>((min_triangles + 2 * ring - 1) / (2 * ring));
  constexpr float kTwoPi = 6.28318530717958647692f;
  IndexedMesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(segments) * ring);
  // Rotation-minimising frame by projection; the frame does not close exactly at the
  // seam, which only twists one ring of quads.
  vec3 normal(0.0f, 0.0f, 1.0f);
  for (std::uint32_t i = 0; i < segments; ++i) {
    const float s = kTwoPi * static_cast<float>(i) / static_cast<float>(segments);
    const float ds = 1e-3f;
    const vec3 center = knot_curve(s);
    const vec3 tangent = glm::normalize(knot_curve(s + ds) - knot_curve(s - ds));
    normal = normal - glm::dot(normal, tangent) * tangent;
    if (glm::dot(normal, normal) < 1e-12f) normal = glm::cross(tangent, vec3(1.0f, 0.0f, 0.0f));
    normal = glm::normalize(normal);
    const vec3 binormal = glm::cross(tangent, normal);
    for (std::uint32_t j = 0; j < ring; ++j) {
      const float theta = kTwoPi * static_cast<float>(j) / ring;
      const float bump = 1.0f + 0.15f * std::sin(11.0f * theta) * std::sin(97.0f * s) +
                         0.05f * std::sin(3.0f * theta + 211.0f * s);
      const float radius = 0.3f * bump;
      mesh.positions.push_back(center +
                               radius * (std::cos(theta) * normal + std::sin(theta) * binormal));
    }
  }
  mesh.indices.reserve(static_cast<std::size_t>(segments) * ring * 6);
  for (std::uint32_t i = 0; i < segments; ++i) {
    const std::uint32_t i1 = (i + 1) % segments;
    for (std::uint32_t j = 0; j < ring; ++j) {
      const std::uint32_t j1 = (j + 1) % ring;
      const std::uint32_t a = i * ring + j, b = i1 * ring + j, c = i1 * ring + j1,
                          d = i * ring + j1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  }
  return mesh;
}

// Unit icosphere: an icosahedron with each triangle split in four `levels` times.
IndexedMesh make_icosphere(int levels) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  IndexedMesh mesh;
  for (const vec3& p : {vec3(-1, t, 0), vec3(1, t, 0), vec3(-1, -t, 0), vec3(1, -t, 0),
                        vec3(0, -1, t), vec3(0, 1, t), vec3(0, -1, -t), vec3(0, 1, -t),
                        vec3(t, 0, -1), vec3(t, 0, 1), vec3(-t, 0, -1), vec3(-t, 0, 1)})
    mesh.positions.push_back(glm::normalize(p));
  mesh.indices = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                  4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                  6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoints.try_emplace({key.first, key.second}, 0u);
      if (inserted) {
        it->second = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(glm::normalize(mesh.positions[a] + mesh.positions[b]));
      }
      return it->second;
    };
    std::vector<std::uint32_t> next;
    next.reserve(mesh.indices.size() * 4);
    for (std::size_t f = 0; f < mesh.indices.size(); f += 3) {
      const std::uint32_t a = mesh.indices[f], b = mesh.indices[f + 1], c = mesh.indices[f + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    mesh.indices = std::move(next);
  }
  return mesh;
}

IndexedMesh make_scatter(std::size_t min_triangles) {
  const IndexedMesh sphere = make_icosphere(2);  // 320 triangles
  const std::size_t count = (min_triangles + sphere.triangle_count() - 1) / sphere.triangle_count();
  IndexedMesh mesh;
  mesh.positions.reserve(count * sphere.positions.size());
  mesh.indices.reserve(count * sphere.indices.size());
  constexpr std::uint64_t kStream = 0x5ca77e2;
  for (std::size_t s = 0; s < count; ++s) {
    const vec3 center(2.0f * random_unit(kStream, 4 * s) - 1.0f,
                      2.0f * random_unit(kStream, 4 * s + 1) - 1.0f,
                      2.0f * random_unit(kStream, 4 * s + 2) - 1.0f);
    const float radius = 0.01f + 0.07f * random_unit(kStream, 4 * s + 3);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (const vec3& p : sphere.positions) mesh.positions.push_back(center + radius * p);
    for (std::uint32_t index : sphere.indices) mesh.indices.push_back(base + index);
  }
  return mesh;
}

}  // namespace

std::optional<SyntheticMesh> parse_synthetic_mesh(std::string_view name) {
  if (name == "knot") return SyntheticMesh::kKnot;
  if (name == "scatter") return SyntheticMesh::kScatter;
  return std::nullopt;
}

IndexedMesh make_synthetic_mesh(SyntheticMesh kind, std::size_t min_triangles) {
  return kind == SyntheticMesh::kKnot ? make_knot(min_triangles) : make_scatter(min_triangles);
}

}  // namespace tessera::bench
