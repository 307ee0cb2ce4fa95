#include "mesh_sharing.hpp"

#include "tessera/render/accel_builder.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "mesh_triangles.hpp"
#include "repeated_triangles.hpp"
#include "shape_placement.hpp"

namespace tessera {

namespace {

bool same_geometry(const TriangleMeshDesc& a, const TriangleMeshDesc& b) {
  return a.indices == b.indices && a.positions == b.positions && a.normals == b.normals &&
         a.uvs == b.uvs;
}

// FNV-1a over the geometry's 8-byte words (every array holds whole words but the
// indices, whose odd tail is mixed alone): equal meshes hash alike, same_geometry confirms.
// Word-wise, it costs about as much as reading the mesh once.
std::uint64_t geometry_hash(const TriangleMeshDesc& mesh) {
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t word;
      std::memcpy(&word, p + i, 8);
      h = (h ^ word) * 1099511628211ull;
    }
    for (; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  mix(mesh.positions.data(), mesh.positions.size() * sizeof(glm::dvec3));
  mix(mesh.normals.data(), mesh.normals.size() * sizeof(glm::dvec3));
  mix(mesh.uvs.data(), mesh.uvs.size() * sizeof(glm::dvec2));
  return h;
}

}  // namespace

SharedGeometryGroups shared_geometry_groups(const SceneDescription& description,
                                            std::span<const Material> materials) {
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_hash;  // into `groups`
  SharedGeometryGroups groups;
  for (std::size_t m = 0; m < description.meshes.size(); ++m) {
    const TriangleMeshDesc& mesh = description.meshes[m];
    if (!mesh.visible || mesh.indices.size() < 3 || materials[mesh.material].emissive()) continue;
    auto& candidates = by_hash[geometry_hash(mesh)];
    const auto same = std::find_if(candidates.begin(), candidates.end(), [&](std::size_t g) {
      return same_geometry(description.meshes[groups[g].front()], mesh);
    });
    if (same != candidates.end()) {
      groups[*same].push_back(m);
    } else {
      candidates.push_back(groups.size());
      groups.push_back({m});
    }
  }
  std::erase_if(groups, [](const auto& group) { return group.size() < 2; });
  return groups;
}

SharedMeshes share_mesh_geometry(const SceneDescription& description,
                                 const SharedGeometryGroups& groups, bool store_attributes) {
  SharedMeshes shared;
  shared.geometries.reserve(groups.size());  // the instances point into it
  std::vector<MeshInstance> instances;
  std::uint64_t next_id = 0;
  for (const auto& group : groups) {
    const TriangleMeshDesc& geometry = description.meshes[group.front()];
    const auto first_triangle = static_cast<std::uint32_t>(shared.triangles.size());
    const std::vector<bool> repeated = repeated_triangles(geometry);
    for (std::size_t i = 0; i + 2 < geometry.indices.size(); i += 3) {
      if (!repeated.empty() && repeated[i / 3]) continue;  // adds nothing to the image
      const std::uint32_t a = geometry.indices[i], b = geometry.indices[i + 1],
                          c = geometry.indices[i + 2];
      // Material 0: each placement carries its own material (MeshPlacement::material).
      shared.triangles.push_back(mesh_triangle(geometry, a, b, c, 0));
      if (store_attributes) shared.attributes.push_back(mesh_attributes(geometry, a, b, c));
    }
    const std::span<const Triangle> object(shared.triangles.data() + first_triangle,
                                           shared.triangles.size() - first_triangle);
    shared.geometries.push_back(
        TriangleAccel::build(object, accel_build_options(description.render.accel_builder)));
    for (const std::size_t m : group) {
      const TriangleMeshDesc& entry = description.meshes[m];
      if (next_id + object.size() > std::uint64_t{kPrimitiveIndexMask} + 1)
        throw std::invalid_argument(
            "geometry[" + std::to_string(entry.source_index) +
            "]: placements of shared meshes exceed 2^27 triangles in all (the reference's "
            "index bits)");
      MeshPlacement placement;
      placement.first_id = static_cast<std::uint32_t>(next_id);
      placement.first_triangle = first_triangle;
      placement.material = entry.material;
      placement.object_to_world = Placement(entry.transform).affine;
      placement.world_to_object = placement.object_to_world.inverse();
      placement.world_position_error_gain = placement.object_to_world.max_error_gain();
      shared.placements.push_back(placement);
      instances.push_back(
          MeshInstance{&shared.geometries.back(),
                       entry.transform ? glm::mat4(entry.transform->matrix()) : glm::mat4(1.0f),
                       make_primitive_ref(PrimitiveType::kInstancedTriangle, placement.first_id)});
      next_id += object.size();
    }
  }
  if (!instances.empty()) {
    shared.top_level = InstanceAccel(std::move(instances));
    spdlog::info("{} mesh placements share {} geometries (two-level)", shared.placements.size(),
                 shared.geometries.size());
  }
  return shared;
}

}  // namespace tessera
