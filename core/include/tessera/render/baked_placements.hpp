#pragma once
// Shared mesh placements baked into world triangles, for the device layout
// (render/device_scene_source.hpp). The CPU traces a mesh placed two or more times through
// one object-space structure per geometry and an instance level above them; device code walks
// one binary BVH with no instance level, so there each placement becomes world triangles of
// its own, as `instancing: false` would have stored it. That costs memory in proportion to
// the placements, so the device path takes it only up to a limit.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "tessera/geometry/triangle.hpp"
#include "tessera/geometry/triangle_attributes.hpp"
#include "tessera/render/scene_data.hpp"

namespace tessera {

// The most triangles the device layout bakes out of shared placements: at about 140 bytes a
// triangle with normals and uvs (40 the triangle, 60 its attributes, 36 its share of the
// binary BVH's nodes, 4 its reference), 1.1 GiB on the host and as much on the device.
inline constexpr std::size_t kMaxDeviceBakedTriangles = std::size_t{1} << 23;

struct BakedPlacements {
  std::vector<Triangle> triangles;  // every placement's in turn, in the placements' order
  std::vector<TriangleAttributes> attributes;  // likewise; empty when none are stored
};

// How many triangles baking `placements` gives: each placement's geometry runs from its
// first_triangle to the next geometry's (placements of one geometry share first_triangle)
// or to the end of the `object_triangle_count` object-space triangles.
std::size_t baked_placement_triangles(std::span<const MeshPlacement> placements,
                                      std::size_t object_triangle_count);

// Why the device layout does not bake `baked` triangles beside the scene's own
// `stored_triangles`, or "" when it does: more than `limit`, or more triangle references
// than a primitive reference holds.
std::string baked_placements_refusal(std::size_t baked, std::size_t stored_triangles,
                                     std::size_t limit = kMaxDeviceBakedTriangles);

// Every placement's triangles in world space: vertices through object_to_world in double,
// vertex normals by placed_vertex_normal, uvs as they are, the placement's material.
// `object_attributes` is empty or parallel to `object_triangles`.
BakedPlacements bake_placements(std::span<const MeshPlacement> placements,
                                std::span<const Triangle> object_triangles,
                                std::span<const TriangleAttributes> object_attributes);

}  // namespace tessera
