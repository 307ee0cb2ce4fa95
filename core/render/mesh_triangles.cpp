#include "mesh_triangles.hpp"

#include <algorithm>

#include "repeated_triangles.hpp"

namespace tessera {

bool stores_triangle_attributes(std::span<const TriangleMeshDesc> meshes) {
  return std::any_of(meshes.begin(), meshes.end(), [](const TriangleMeshDesc& m) {
    return !m.normals.empty() || !m.uvs.empty();
  });
}

Triangle mesh_triangle(const TriangleMeshDesc& mesh, std::uint32_t a, std::uint32_t b,
                       std::uint32_t c, std::uint32_t material) {
  return Triangle{vec3(mesh.positions[a]), vec3(mesh.positions[b]), vec3(mesh.positions[c]),
                  material};
}

TriangleAttributes mesh_attributes(const TriangleMeshDesc& mesh, std::uint32_t a, std::uint32_t b,
                                   std::uint32_t c) {
  TriangleAttributes shading{vec3(0.0f), vec3(0.0f),       vec3(0.0f),
                             vec2(0.0f), vec2(1.0f, 0.0f), vec2(0.0f, 1.0f)};
  if (mesh.normals.size() == mesh.positions.size()) {
    shading.n0 = vec3(mesh.normals[a]);
    shading.n1 = vec3(mesh.normals[b]);
    shading.n2 = vec3(mesh.normals[c]);
  }
  if (mesh.uvs.size() == mesh.positions.size()) {
    shading.uv0 = vec2(mesh.uvs[a]);
    shading.uv1 = vec2(mesh.uvs[b]);
    shading.uv2 = vec2(mesh.uvs[c]);
  }
  return shading;
}

void bake_mesh(const TriangleMeshDesc& mesh, bool store_attributes,
               std::vector<Triangle>& triangles, std::vector<TriangleAttributes>& attributes,
               PrimitiveList& primitives) {
  const TriangleMeshDesc world =
      mesh.transform ? transformed_mesh(mesh, *mesh.transform) : TriangleMeshDesc{};
  const TriangleMeshDesc& placed = mesh.transform ? world : mesh;
  const std::vector<bool> repeated = repeated_triangles(placed);
  for (std::size_t i = 0; i + 2 < placed.indices.size(); i += 3) {
    if (!repeated.empty() && repeated[i / 3]) continue;  // adds nothing to the image
    const std::uint32_t a = placed.indices[i], b = placed.indices[i + 1], c = placed.indices[i + 2];
    primitives.store(triangles, PrimitiveType::kTriangle,
                     mesh_triangle(placed, a, b, c, placed.material), placed.visible,
                     placed.material);
    if (store_attributes) attributes.push_back(mesh_attributes(placed, a, b, c));
  }
}

}  // namespace tessera
