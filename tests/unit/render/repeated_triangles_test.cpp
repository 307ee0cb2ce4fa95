// A mesh that repeats a triangle renders like the mesh without the repeats: the renderer
// keeps one copy (so a million copies cost what one does) and the image is the same bit
// for bit. Triangles that differ in winding, or in a normal, are not repeats.
#include <gtest/gtest.h>

#include <cstring>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

SceneDescription cornell_with(TriangleMeshDesc mesh) {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  scene.render.width = 32;
  scene.render.height = 32;
  scene.render.samples_per_pixel = 4;
  mesh.source_index = static_cast<std::uint32_t>(scene.analytic_shape_count());
  scene.meshes.push_back(std::move(mesh));
  return scene;
}

TriangleMeshDesc triangle_mesh(std::size_t copies, bool with_transform) {
  TriangleMeshDesc mesh;
  mesh.positions = {{-0.3, 0.8, 0.6}, {0.3, 0.8, 0.6}, {0.0, 1.3, 0.6}};
  for (std::size_t i = 0; i < copies; ++i) {
    // Every other copy starts at another corner: the same triangle, the same winding.
    const std::uint32_t first = static_cast<std::uint32_t>(i % 3);
    mesh.indices.insert(mesh.indices.end(), {first, (first + 1) % 3, (first + 2) % 3});
  }
  if (with_transform) {
    TransformDesc transform;
    transform.translate = {0.1, 0.0, 0.0};
    mesh.transform = transform;
  }
  return mesh;
}

bool bit_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(RepeatedTriangles, ManyCopiesRenderAndCostLikeOne) {
  for (const bool transformed : {false, true}) {
    SCOPED_TRACE(transformed ? "transformed" : "as written");
    const auto one = PreparedScene::build(cornell_with(triangle_mesh(1, transformed)));
    const auto many = PreparedScene::build(cornell_with(triangle_mesh(100'000, transformed)));
    EXPECT_EQ(many->triangle_bytes(), one->triangle_bytes());
    EXPECT_TRUE(bit_equal(render_image(*many), render_image(*one)));
  }
}

TEST(RepeatedTriangles, OtherWindingOrOtherNormalsAreKept) {
  TriangleMeshDesc flipped = triangle_mesh(1, false);
  flipped.indices.insert(flipped.indices.end(), {0, 2, 1});
  EXPECT_GT(PreparedScene::build(cornell_with(flipped))->triangle_bytes(),
            PreparedScene::build(cornell_with(triangle_mesh(1, false)))->triangle_bytes());

  // Two triangles over the same positions but with their own vertices and normals.
  TriangleMeshDesc shaded;
  shaded.positions = {{-0.3, 0.8, 0.6}, {0.3, 0.8, 0.6}, {0.0, 1.3, 0.6},
                      {-0.3, 0.8, 0.6}, {0.3, 0.8, 0.6}, {0.0, 1.3, 0.6}};
  shaded.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 1}, {0, 1, 1}, {0, 1, 1}};
  shaded.indices = {0, 1, 2, 3, 4, 5};
  TriangleMeshDesc same = shaded;
  same.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_GT(PreparedScene::build(cornell_with(shaded))->triangle_bytes(),
            PreparedScene::build(cornell_with(same))->triangle_bytes());
}

}  // namespace
}  // namespace tessera
