#include "tessera/render/baked_placements.hpp"

#include <algorithm>
#include <numeric>

namespace tessera {

namespace {

// Each placement's triangle count: its geometry runs from its first_triangle to the next
// geometry's start (placements of one geometry share first_triangle) or to the end.
std::vector<std::size_t> placement_sizes(std::span<const MeshPlacement> placements,
                                         std::size_t object_triangle_count) {
  std::vector<std::uint32_t> starts;
  starts.reserve(placements.size());
  for (const MeshPlacement& p : placements) starts.push_back(p.first_triangle);
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  std::vector<std::size_t> sizes;
  sizes.reserve(placements.size());
  for (const MeshPlacement& p : placements) {
    const auto next = std::upper_bound(starts.begin(), starts.end(), p.first_triangle);
    sizes.push_back((next == starts.end() ? object_triangle_count : *next) - p.first_triangle);
  }
  return sizes;
}

}  // namespace

std::size_t baked_placement_triangles(std::span<const MeshPlacement> placements,
                                      std::size_t object_triangle_count) {
  const std::vector<std::size_t> sizes = placement_sizes(placements, object_triangle_count);
  return std::accumulate(sizes.begin(), sizes.end(), std::size_t{0});
}

std::string baked_placements_refusal(std::size_t baked, std::size_t stored_triangles,
                                     std::size_t limit) {
  if (baked > limit)
    return "meshes placed more than once would bake into " + std::to_string(baked) +
           " triangles for the device, more than its limit of " + std::to_string(limit);
  if (stored_triangles + baked > std::size_t{kPrimitiveIndexMask} + 1)
    return std::to_string(stored_triangles + baked) +
           " triangles with the baked placements are more than a primitive reference can name (" +
           std::to_string(std::size_t{kPrimitiveIndexMask} + 1) + ")";
  return "";
}

BakedPlacements bake_placements(std::span<const MeshPlacement> placements,
                                std::span<const Triangle> object_triangles,
                                std::span<const TriangleAttributes> object_attributes) {
  const std::vector<std::size_t> sizes = placement_sizes(placements, object_triangles.size());
  const bool attributes = !object_attributes.empty();
  const std::size_t total = std::accumulate(sizes.begin(), sizes.end(), std::size_t{0});
  BakedPlacements out;
  out.triangles.reserve(total);
  if (attributes) out.attributes.reserve(total);
  for (std::size_t k = 0; k < placements.size(); ++k) {
    const MeshPlacement& p = placements[k];
    const auto world = [&p](const vec3& v) { return vec3(p.object_to_world.point(dvec3(v))); };
    const glm::dmat3 normal_matrix = glm::transpose(p.world_to_object.linear);
    for (std::size_t i = p.first_triangle; i < p.first_triangle + sizes[k]; ++i) {
      const Triangle& t = object_triangles[i];
      out.triangles.push_back(Triangle{world(t.p0), world(t.p1), world(t.p2), p.material});
      if (!attributes) continue;
      const TriangleAttributes& a = object_attributes[i];
      out.attributes.push_back(TriangleAttributes{
          placed_vertex_normal(normal_matrix, a.n0), placed_vertex_normal(normal_matrix, a.n1),
          placed_vertex_normal(normal_matrix, a.n2), a.uv0, a.uv1, a.uv2});
    }
  }
  return out;
}

}  // namespace tessera
