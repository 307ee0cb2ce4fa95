#pragma once
// Mesh sharing: geometry placed two or more times is stored once in object space, with one
// TriangleAccel, and each placement becomes an instance of it (two-level: InstanceAccel over
// the placements) instead of a baked copy.
#include <cstddef>
#include <span>
#include <vector>

#include "tessera/accel/instance_accel.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Groups of mesh entries (indices into SceneDescription::meshes) that place one geometry.
using SharedGeometryGroups = std::vector<std::vector<std::size_t>>;

// The entries sharing a geometry, for every geometry placed two or more times by visible,
// non-emitting entries. Found by content, so scenes that arrive over the API share as well
// as those whose loader shared the file. Emitters stay baked: lights are sampled per world
// triangle.
SharedGeometryGroups shared_geometry_groups(const SceneDescription& description,
                                            std::span<const Material> materials);

// The shared geometries of one scene as the renderer stores them.
struct SharedMeshes {
  // Object-space triangles of every geometry back to back, and their attributes (empty
  // unless attributes are stored).
  std::vector<Triangle> triangles;
  std::vector<TriangleAttributes> attributes;
  // One structure per geometry. The top level points at them: moving the vector keeps them
  // where they are, copying or growing it would not.
  std::vector<TriangleAccel> geometries;
  std::vector<MeshPlacement> placements;  // sorted by first_id
  InstanceAccel top_level;                // over the placements; empty when there are none
};

// Builds each group's geometry once, from its first entry, and every entry of the group as
// a placement with its own range of virtual triangle ids (PrimitiveType::kInstancedTriangle).
// Throws std::invalid_argument when the ids exceed a primitive reference's index bits.
SharedMeshes share_mesh_geometry(const SceneDescription& description,
                                 const SharedGeometryGroups& groups, bool store_attributes);

}  // namespace tessera
