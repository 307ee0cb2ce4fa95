// Mesh files through assimp: triangulation, normals and uvs kept, and errors that name the
// file and assimp's reason for malformed or empty files.
#include "tessera/scene/mesh_loader.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tessera/scene/scene_error.hpp"

namespace tessera {
namespace {

class MeshLoaderTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("tessera_mesh_loader_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path write(const std::string& name, const std::string& content) const {
    const auto path = dir_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  std::filesystem::path dir_;
};

TEST_F(MeshLoaderTest, ObjQuadIsTriangulatedWithNormalsAndUvs) {
  const auto path = write("quad.obj",
                          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                          "vn 0 0 1\n"
                          "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  const TriangleMeshDesc mesh = load_mesh_file(path);
  ASSERT_EQ(mesh.indices.size(), 6u);  // one quad, two triangles
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    EXPECT_EQ(mesh.normals[v], glm::dvec3(0, 0, 1));
    // This file's uvs equal the vertices' x and y.
    EXPECT_EQ(mesh.uvs[v], glm::dvec2(mesh.positions[v].x, mesh.positions[v].y));
  }
  EXPECT_EQ(mesh.source_file, path.string());
}

TEST_F(MeshLoaderTest, BinaryPlyWithoutNormalsLoadsPositionsOnly) {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  const float vertices[9] = {0, 0, 0, 2, 0, 0, 0, 3, 0};
  ply.append(reinterpret_cast<const char*>(vertices), sizeof vertices);
  ply.push_back(3);
  const std::uint32_t face[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(face), sizeof face);
  const TriangleMeshDesc mesh = load_mesh_file(write("tri.ply", ply));
  ASSERT_EQ(mesh.indices.size(), 3u);
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_EQ(mesh.positions[mesh.indices[1]], glm::dvec3(2, 0, 0));
  EXPECT_TRUE(mesh.uvs.empty());
}

void expect_error_naming(const std::filesystem::path& path, const std::string& reason_part) {
  try {
    load_mesh_file(path);
    FAIL() << "no error for " << path;
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(reason_part), std::string::npos) << message;
  }
}

TEST_F(MeshLoaderTest, EmptyMalformedAndMissingFilesAreErrorsNamingTheFile) {
  expect_error_naming(write("empty.obj", ""), "cannot read mesh");
  // A PLY header without end_header: assimp alone would never return.
  expect_error_naming(
      write("garbage.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 99\nend"),
      "end_header");
  expect_error_naming(write("ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend"),
                      "end_header");
  expect_error_naming(write("noise.stl", std::string(100, '\x7f')), "cannot read mesh");
  expect_error_naming(dir_ / "missing.obj", "not found");
  // Only points and lines: readable, but nothing to render.
  expect_error_naming(write("lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n"), "");
}

TEST(MeshLoaderShared, SuzanneSub4LoadsEveryTriangle) {
  const std::filesystem::path path =
      std::filesystem::path(TESSERA_SHARED_DIR) / "meshes" / "suzanne-sub4.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
  const TriangleMeshDesc mesh = load_mesh_file(path);
  EXPECT_EQ(mesh.indices.size(), 3u * 251904u);
  EXPECT_EQ(mesh.positions.size(), 126290u);
}

}  // namespace
}  // namespace tessera
