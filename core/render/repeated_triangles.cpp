#include "repeated_triangles.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <utility>

namespace tessera {
namespace {

// One vertex's data as the renderer reads it; compared bit for bit.
class VertexView {
 public:
  explicit VertexView(const TriangleMeshDesc& mesh)
      : mesh_(mesh),
        normals_(mesh.normals.size() == mesh.positions.size()),
        uvs_(mesh.uvs.size() == mesh.positions.size()) {}

  // Lexicographic order on the vertex's bytes, so a triangle has one first corner.
  int compare(std::uint32_t a, std::uint32_t b) const {
    if (a == b) return 0;
    if (const int c = std::memcmp(&mesh_.positions[a], &mesh_.positions[b], sizeof(glm::dvec3)))
      return c;
    if (normals_)
      if (const int c = std::memcmp(&mesh_.normals[a], &mesh_.normals[b], sizeof(glm::dvec3)))
        return c;
    if (uvs_) return std::memcmp(&mesh_.uvs[a], &mesh_.uvs[b], sizeof(glm::dvec2));
    return 0;
  }

  std::uint64_t hash(std::uint32_t v, std::uint64_t h) const {
    h = mix(h, &mesh_.positions[v], sizeof(glm::dvec3));
    if (normals_) h = mix(h, &mesh_.normals[v], sizeof(glm::dvec3));
    if (uvs_) h = mix(h, &mesh_.uvs[v], sizeof(glm::dvec2));
    return h;
  }

 private:
  // FNV-1a over 8-byte words.
  static std::uint64_t mix(std::uint64_t h, const void* data, std::size_t size) {
    for (std::size_t offset = 0; offset < size; offset += 8) {
      std::uint64_t word;
      std::memcpy(&word, static_cast<const char*>(data) + offset, 8);
      h = (h ^ word) * 0x100000001b3ULL;
    }
    return h;
  }

  const TriangleMeshDesc& mesh_;
  bool normals_;
  bool uvs_;
};

// The triangle's corners rotated to start at its smallest vertex (winding kept).
std::array<std::uint32_t, 3> canonical(const TriangleMeshDesc& mesh, const VertexView& view,
                                       std::size_t triangle) {
  const std::uint32_t* v = &mesh.indices[triangle * 3];
  std::size_t first = 0;
  for (std::size_t i = 1; i < 3; ++i)
    if (view.compare(v[i], v[first]) < 0) first = i;
  return {v[first], v[(first + 1) % 3], v[(first + 2) % 3]};
}

}  // namespace

std::vector<bool> repeated_triangles(const TriangleMeshDesc& mesh) {
  const std::size_t count = mesh.indices.size() / 3;
  if (count < 2) return {};
  const VertexView view(mesh);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(count);
  for (std::size_t t = 0; t < count; ++t) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const std::uint32_t v : canonical(mesh, view, t)) h = view.hash(v, h);
    keys[t] = {h, static_cast<std::uint32_t>(t)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<bool> repeated;
  for (std::size_t run = 0; run < keys.size();) {
    std::size_t end = run + 1;
    while (end < keys.size() && keys[end].first == keys[run].first) ++end;
    // Within a run of equal hashes (in triangle order), each triangle is compared with the
    // kept ones before it: one in the common case, more only on a hash collision.
    std::vector<std::array<std::uint32_t, 3>> kept;
    for (std::size_t k = run; k < end; ++k) {
      const auto corners = canonical(mesh, view, keys[k].second);
      const bool same = std::any_of(kept.begin(), kept.end(), [&](const auto& other) {
        return view.compare(corners[0], other[0]) == 0 && view.compare(corners[1], other[1]) == 0 &&
               view.compare(corners[2], other[2]) == 0;
      });
      if (same) {
        if (repeated.empty()) repeated.assign(count, false);
        repeated[keys[k].second] = true;
      } else {
        kept.push_back(corners);
      }
    }
    run = end;
  }
  return repeated;
}

}  // namespace tessera
