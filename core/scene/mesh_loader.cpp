#include "tessera/scene/mesh_loader.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <cctype>
#include <fstream>
#include <string>

#include "tessera/scene/scene_error.hpp"

namespace tessera {

TriangleMeshDesc load_mesh_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw SceneError(SceneIssue{path.string(), 0, "", "mesh file not found or not a regular file"});

  // assimp 5.2 never returns from a PLY file whose header lacks `end_header`; refuse those
  // before handing the file over.
  {
    std::ifstream in(path, std::ios::binary);
    std::string head(65536, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    if (head.rfind("ply", 0) == 0 && head.find("end_header") == std::string::npos)
      throw SceneError(
          SceneIssue{path.string(), 0, "",
                     "cannot read mesh: PLY header has no end_header in its first 64 KiB"});
  }

  Assimp::Importer importer;
  // Drop what rendering does not use so the import is faster and uses less memory (normals
  // and uvs are kept).
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_COLORS | aiComponent_TEXTURES |
                                                          aiComponent_LIGHTS | aiComponent_CAMERAS |
                                                          aiComponent_ANIMATIONS |
                                                          aiComponent_MATERIALS);
  // Joining identical vertices is only worth its cost for formats that store every face
  // corner separately (OBJ, STL, ...): for PLY and glTF, which are indexed already, it
  // found nothing to join and took two thirds of the load (0.45 of 0.65 s for the 1M
  // triangle suzanne-sub5.ply).
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool indexed = extension == ".ply" || extension == ".gltf" || extension == ".glb";
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | (indexed ? 0u : aiProcess_JoinIdenticalVertices) |
                         aiProcess_RemoveComponent | aiProcess_SortByPType |
                         aiProcess_PreTransformVertices);
  if (scene == nullptr)
    throw SceneError(SceneIssue{path.string(), 0, "",
                                std::string("cannot read mesh: ") + importer.GetErrorString()});

  TriangleMeshDesc mesh;
  mesh.source_file = path.string();
  // Normals and uvs are kept when every triangle mesh in the file has them, so the arrays
  // stay parallel to the positions.
  bool all_normals = true, all_uvs = true;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    all_normals = all_normals && in->HasNormals();
    all_uvs = all_uvs && in->HasTextureCoords(0);
  }
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      mesh.positions.emplace_back(p.x, p.y, p.z);
      if (all_normals)
        mesh.normals.emplace_back(in->mNormals[v].x, in->mNormals[v].y, in->mNormals[v].z);
      if (all_uvs) mesh.uvs.emplace_back(in->mTextureCoords[0][v].x, in->mTextureCoords[0][v].y);
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by SortByPType
      for (int k = 0; k < 3; ++k) mesh.indices.push_back(base + face.mIndices[k]);
    }
  }
  for (std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size())
      throw SceneError(SceneIssue{path.string(), 0, "",
                                  "cannot read mesh: vertex index " + std::to_string(index) +
                                      " out of range (" + std::to_string(mesh.positions.size()) +
                                      " vertices)"});
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
