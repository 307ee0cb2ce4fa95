#include "tessera/scene/mesh_loader.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "tessera/scene/scene_error.hpp"

namespace tessera {

TriangleMeshDesc load_mesh_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw SceneError(SceneIssue{path.string(), 0, "", "mesh file not found or not a regular file"});

  Assimp::Importer importer;
  // Drop what rendering does not use so the import is faster and uses less memory.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_COLORS | aiComponent_TEXTURES |
                                                          aiComponent_LIGHTS | aiComponent_CAMERAS |
                                                          aiComponent_ANIMATIONS |
                                                          aiComponent_MATERIALS);
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_RemoveComponent | aiProcess_SortByPType |
                                           aiProcess_PreTransformVertices);
  if (scene == nullptr)
    throw SceneError(SceneIssue{path.string(), 0, "",
                                std::string("cannot read mesh: ") + importer.GetErrorString()});

  TriangleMeshDesc mesh;
  mesh.source_file = path.string();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      mesh.positions.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by SortByPType
      for (int k = 0; k < 3; ++k) mesh.indices.push_back(base + face.mIndices[k]);
    }
  }
  if (mesh.indices.empty())
    throw SceneError(SceneIssue{path.string(), 0, "", "mesh file contains no triangles"});
  return mesh;
}

bool path_is_within(const std::filesystem::path& path,
                    const std::vector<std::filesystem::path>& roots) {
  std::error_code ec;
  const auto resolved = std::filesystem::weakly_canonical(path, ec);
  if (ec) return false;
  for (const auto& root : roots) {
    const auto canonical_root = std::filesystem::weakly_canonical(root, ec);
    if (ec) continue;
    auto r = canonical_root.begin();
    auto p = resolved.begin();
    for (; r != canonical_root.end() && p != resolved.end() && *r == *p; ++r, ++p) {
    }
    // A trailing empty element means the root was written with a final slash.
    if (r == canonical_root.end() || (std::next(r) == canonical_root.end() && r->empty()))
      return true;
  }
  return false;
}

}  // namespace tessera
