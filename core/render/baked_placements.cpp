#include "tessera/render/baked_placements.hpp"

#include <algorithm>

namespace tessera {

namespace {

// The triangle count of the geometry starting at `first`: up to the next geometry's start.
std::size_t geometry_size(std::span<const std::uint32_t> starts, std::uint32_t first,
                          std::size_t object_triangle_count) {
  const auto next = std::upper_bound(starts.begin(), starts.end(), first);
  return (next == starts.end() ? object_triangle_count : *next) - first;
}

std::vector<std::uint32_t> geometry_starts(std::span<const MeshPlacement> placements) {
  std::vector<std::uint32_t> starts;
  starts.reserve(placements.size());
  for (const MeshPlacement& p : placements) starts.push_back(p.first_triangle);
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  return starts;
}

}  // namespace

std::size_t baked_placement_triangles(std::span<const MeshPlacement> placements,
                                      std::size_t object_triangle_count) {
  const std::vector<std::uint32_t> starts = geometry_starts(placements);
  std::size_t total = 0;
  for (const MeshPlacement& p : placements)
    total += geometry_size(starts, p.first_triangle, object_triangle_count);
  return total;
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
  const std::vector<std::uint32_t> starts = geometry_starts(placements);
  const bool attributes = !object_attributes.empty();
  BakedPlacements out;
  const std::size_t total = baked_placement_triangles(placements, object_triangles.size());
  out.triangles.reserve(total);
  if (attributes) out.attributes.reserve(total);
  for (const MeshPlacement& p : placements) {
    const auto world = [&p](const vec3& v) { return vec3(p.object_to_world.point(dvec3(v))); };
    const glm::dmat3 normal_matrix = glm::transpose(p.world_to_object.linear);
    const std::size_t count = geometry_size(starts, p.first_triangle, object_triangles.size());
    for (std::size_t i = p.first_triangle; i < p.first_triangle + count; ++i) {
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
