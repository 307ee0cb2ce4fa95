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

// A unit vector from two uniform numbers (uniform on the sphere).
vec3 unit_vector(float u, float v) {
  constexpr float kTwoPi = 6.28318530717958647692f;
  const float z = 2.0f * u - 1.0f;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return vec3(r * std::cos(kTwoPi * v), r * std::sin(kTwoPi * v), z);
}

// Appends `part` moved to `center` and scaled by `radius`.
void append_scaled(IndexedMesh& mesh, const IndexedMesh& part, const vec3& center, float radius) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (const vec3& p : part.positions) mesh.positions.push_back(center + radius * p);
  for (std::uint32_t index : part.indices) mesh.indices.push_back(base + index);
}

void append_quad(IndexedMesh& mesh, const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
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
    append_scaled(mesh, sphere, center, radius);
  }
  return mesh;
}

IndexedMesh make_tubes(std::size_t min_triangles, TubeTessellation tess) {
  constexpr float kLength = 8.0f, kRadius = 0.15f, kTwoPi = 6.28318530717958647692f;
  const std::uint32_t strips = std::max(3u, tess.strips), rings = std::max(1u, tess.rings);
  const std::size_t per_tube = std::size_t{2} * strips * rings;
  const std::size_t count = (min_triangles + per_tube - 1) / per_tube;
  // 3,000 tubes fill a cube of side 24; more or fewer keep that density.
  const float half = 12.0f * std::cbrt(static_cast<float>(count) / 3000.0f);
  constexpr std::uint64_t kStream = 0x7ab35;
  IndexedMesh mesh;
  mesh.positions.reserve(count * strips * (rings + 1));
  mesh.indices.reserve(count * per_tube * 3);
  for (std::size_t tube = 0; tube < count; ++tube) {
    const auto random = [&](std::uint64_t k) { return random_unit(kStream, 8 * tube + k); };
    const vec3 center = half * (2.0f * vec3(random(0), random(1), random(2)) - 1.0f);
    const vec3 axis = unit_vector(random(3), random(4));
    const vec3 helper = std::fabs(axis.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    const vec3 u = glm::normalize(glm::cross(axis, helper));
    const vec3 v = glm::cross(axis, u);
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (std::uint32_t ring = 0; ring <= rings; ++ring) {
      const float along = (static_cast<float>(ring) / static_cast<float>(rings) - 0.5f) * kLength;
      for (std::uint32_t s = 0; s < strips; ++s) {
        const float angle = kTwoPi * static_cast<float>(s) / static_cast<float>(strips);
        mesh.positions.push_back(center + along * axis +
                                 kRadius * (std::cos(angle) * u + std::sin(angle) * v));
      }
    }
    for (std::uint32_t ring = 0; ring < rings; ++ring)
      for (std::uint32_t s = 0; s < strips; ++s) {
        const std::uint32_t a0 = base + ring * strips + s;
        const std::uint32_t a1 = base + ring * strips + (s + 1) % strips;
        const std::uint32_t b0 = a0 + strips, b1 = a1 + strips;
        mesh.indices.insert(mesh.indices.end(), {a0, a1, b1, a0, b1, b0});
      }
  }
  return mesh;
}

IndexedMesh make_uneven(std::size_t min_triangles) {
  constexpr float kHalf = 40.0f;  // the ground square is 80 x 80
  constexpr std::uint64_t kStream = 0x0e7e7;
  IndexedMesh mesh;
  // Two huge triangles (edges of 80 and 113) under everything.
  append_quad(mesh, vec3(-kHalf, -kHalf, 0.0f), vec3(kHalf, -kHalf, 0.0f), vec3(kHalf, kHalf, 0.0f),
              vec3(-kHalf, kHalf, 0.0f));
  // Eight large walls (10 to 40 long, 3 to 12 high) at random angles, leaning by up to 30
  // degrees: big triangles whose boxes are far from axis-aligned.
  for (std::uint64_t wall = 0; wall < 8; ++wall) {
    const auto random = [&](std::uint64_t k) { return random_unit(kStream, 1000 + 8 * wall + k); };
    const vec3 foot(kHalf * 1.6f * (random(0) - 0.5f), kHalf * 1.6f * (random(1) - 0.5f), 0.0f);
    const float heading = 6.2831853f * random(2), lean = 0.5236f * (2.0f * random(3) - 1.0f);
    const float length = 10.0f + 30.0f * random(4), height = 3.0f + 9.0f * random(5);
    const vec3 along(std::cos(heading), std::sin(heading), 0.0f);
    const vec3 across(-along.y, along.x, 0.0f);
    const vec3 up = std::cos(lean) * vec3(0.0f, 0.0f, 1.0f) + std::sin(lean) * across;
    const vec3 a = foot - 0.5f * length * along, b = foot + 0.5f * length * along;
    append_quad(mesh, a, b, b + height * up, a + height * up);
  }
  // One dense bumpy sphere of radius 3 (edges about 0.03) holds half the triangles.
  int level = 1;
  while (20u * (std::size_t{1} << (2 * level)) < min_triangles / 2 && level < 9) ++level;
  IndexedMesh dense = make_icosphere(level);
  for (vec3& p : dense.positions)
    p *= 1.0f + 0.08f * std::sin(13.0f * p.x) * std::sin(11.0f * p.y) * std::sin(7.0f * p.z);
  append_scaled(mesh, dense, vec3(0.0f, 0.0f, 3.0f), 3.0f);
  // The rest: 320-triangle spheres resting on the ground, radii log-uniform in [0.005, 2]
  // (edges from about 0.0015 to 0.6).
  const IndexedMesh small = make_icosphere(2);
  for (std::uint64_t s = 0; mesh.triangle_count() < min_triangles; ++s) {
    const auto random = [&](std::uint64_t k) { return random_unit(kStream, 4 * s + k); };
    const float radius = 0.005f * std::pow(400.0f, random(0));
    const vec3 center(kHalf * 1.8f * (random(1) - 0.5f), kHalf * 1.8f * (random(2) - 0.5f), radius);
    append_scaled(mesh, small, center, radius);
  }
  return mesh;
}

}  // namespace

std::optional<SyntheticMesh> parse_synthetic_mesh(std::string_view name) {
  if (name == "knot") return SyntheticMesh::kKnot;
  if (name == "scatter") return SyntheticMesh::kScatter;
  if (name == "tubes") return SyntheticMesh::kTubes;
  if (name == "uneven") return SyntheticMesh::kUneven;
  return std::nullopt;
}

IndexedMesh make_synthetic_mesh(SyntheticMesh kind, std::size_t min_triangles,
                                TubeTessellation tubes) {
  switch (kind) {
    case SyntheticMesh::kKnot:
      return make_knot(min_triangles);
    case SyntheticMesh::kScatter:
      return make_scatter(min_triangles);
    case SyntheticMesh::kTubes:
      return make_tubes(min_triangles, tubes);
    case SyntheticMesh::kUneven:
      break;
  }
  return make_uneven(min_triangles);
}

}  // namespace tessera::bench
