// The scene as a GPU backend uploads it (PreparedScene::device_source): one binary BVH over
// every visible bounded primitive, mesh triangles included, and the flat arrays. Rendered
// on the CPU through that layout (the walk and pipeline nvcc compiles for the device), an
// image must equal the CPU's: both draw the same samples, and a triangle gives the same hit
// bit for bit through a BVH leaf as through the SIMD structure. Only a tie (two surfaces
// at the same distance, as on the shared edge of two triangles) may resolve differently,
// so a few pixels may differ; the test bounds how many. (When this was written, every
// scene here, RayON's included, came out bit for bit the same.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "device_test_scenes.hpp"
#include "scene_materials.hpp"
#include "tessera/render/baked_placements.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

const std::filesystem::path kExamples =
    std::filesystem::path(TESSERA_SOURCE_DIR) / "examples" / "scenes";
const std::filesystem::path kRayonDir = std::filesystem::path(TESSERA_SHARED_DIR) / "rayon-scenes";

struct Comparison {
  std::size_t pixels = 0;
  std::size_t differing = 0;  // pixels whose RGBA is not bit for bit the same
  // pixels with a channel apart by more than float rounding could explain: 1e-4 of the
  // larger value (or 1e-4 absolute, for values below 1)
  std::size_t far_apart = 0;
  double mean_cpu = 0.0;     // mean of the CPU image's RGB
  double mean_device = 0.0;  // mean of the device-layout image's RGB
};

Comparison compare_layouts(const PreparedScene& scene) {
  const RenderSettings& r = scene.settings();
  Comparison c;
  for (const TileRect& tile : make_tiles(r.width, r.height, r.tile_size)) {
    std::vector<float> cpu(tile.pixel_count() * 4), device(tile.pixel_count() * 4);
    scene.render_tile(tile, cpu);
    scene.render_tile_device_layout(tile, device);
    for (std::size_t p = 0; p < tile.pixel_count(); ++p) {
      bool same = true, close = true;
      for (int k = 0; k < 4; ++k) {
        const float a = cpu[4 * p + k], b = device[4 * p + k];
        same = same && a == b;
        close = close && std::fabs(a - b) <= 1e-4f * std::max({1.0f, std::fabs(a), std::fabs(b)});
      }
      c.differing += same ? 0 : 1;
      c.far_apart += close ? 0 : 1;
      for (int k = 0; k < 3; ++k) {
        c.mean_cpu += cpu[4 * p + k];
        c.mean_device += device[4 * p + k];
      }
    }
    c.pixels += tile.pixel_count();
  }
  c.mean_cpu /= 3.0 * static_cast<double>(c.pixels);
  c.mean_device /= 3.0 * static_cast<double>(c.pixels);
  return c;
}

void shrink(RenderSettings& r) {
  device_tests::shrink_for_device_tests(r);
}

// Every primitive reference the CPU traces appears in the device BVH exactly once.
void expect_every_primitive_once(const PreparedScene& scene) {
  const DeviceSceneSource& source = scene.device_source();
  std::multiset<std::uint32_t> seen(source.bvh.primitives.begin(), source.bvh.primitives.end());
  for (std::uint32_t reference : seen) ASSERT_EQ(seen.count(reference), 1u) << reference;
  const SceneView view = scene.view();
  std::size_t expected = 0;
  for (std::uint32_t i = 0; i < view.bvh.node_count; ++i)
    if (view.bvh.nodes[i].is_leaf()) expected += view.bvh.nodes[i].count;
  if (view.bvh.triangles != nullptr) expected += view.bvh.triangles->stats().triangles;
  EXPECT_EQ(source.bvh.primitives.size(), expected);
  // Closest and any hits walk the compressed form: the same references, and the view
  // points at it (so these images test that walk).
  ASSERT_FALSE(source.compressed.nodes.empty());
  EXPECT_EQ(source.view.bvh.compressed_nodes, source.compressed.nodes.data());
  EXPECT_EQ(std::multiset<std::uint32_t>(source.compressed.primitives.begin(),
                                         source.compressed.primitives.end()),
            seen);
  EXPECT_EQ(source.view.bvh.triangles, nullptr);
  EXPECT_EQ(source.view.bvh.wide_nodes, nullptr);
  EXPECT_EQ(source.view.bvh.instances, nullptr);
}

// At most 1% of pixels may differ (ties), and the image's mean by no more than 1%.
void expect_same_image(const PreparedScene& scene, const std::string& name) {
  SCOPED_TRACE(name);
  ASSERT_EQ(scene.device_source().unsupported, "");
  expect_every_primitive_once(scene);
  const Comparison c = compare_layouts(scene);
  EXPECT_LE(c.differing, c.pixels / 100) << c.differing << " of " << c.pixels << " pixels differ";
  EXPECT_NEAR(c.mean_device, c.mean_cpu, 0.01 * c.mean_cpu + 1e-6);
  EXPECT_GT(c.mean_cpu, 0.0);
}

// At 40 x 30 and 4 spp each: see device_test_scenes.hpp for what they cover. The RayON
// scenes below add more where ../shared is present; CI runs without it.
TEST(DeviceLayout, EveryDeviceTestSceneRendersAsOnTheCpu) {
  for (const device_tests::DeviceTestScene& test : device_tests::device_test_scenes())
    expect_same_image(*PreparedScene::build(test.scene), test.name);
}

TEST(DeviceLayout, PatchesAreReportedUnsupported) {
  LoadedScene loaded = load_scene_file(kExamples / "patches.yaml");
  shrink(loaded.scene.render);
  const auto scene = PreparedScene::build(loaded.scene);
  EXPECT_NE(scene->device_source().unsupported.find("patches"), std::string::npos);
  std::vector<float> rgba(16 * 16 * 4);
  EXPECT_THROW(scene->render_tile_device_layout(TileRect{0, 0, 0, 16, 16}, rgba),
               std::invalid_argument);
}

// A mesh large enough for the SIMD structure beside other shapes: its triangles must join
// the device BVH. Placed twice, the mesh is shared (two-level) unless the job bakes it.
SceneDescription mesh_scene(std::uint32_t copies) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.5, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.materials = {test::lambertian_material("white"), test::light_material("light", dvec3(8.0))};
  TriangleMeshDesc grid;
  constexpr int kCells = 24;  // 1,152 triangles: above the shape BVH's share
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const double x = -1.0 + 2.0 * i / kCells, z = -1.0 + 2.0 * j / kCells;
      grid.positions.push_back({x, 0.2 * std::sin(3.0 * x) * std::cos(2.0 * z), z});
    }
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const auto v = static_cast<std::uint32_t>(j * (kCells + 1) + i);
      const std::uint32_t row = kCells + 1;
      for (std::uint32_t k : {v, v + 1, v + row, v + 1, v + row + 1, v + row})
        grid.indices.push_back(k);
    }
  for (std::uint32_t c = 0; c < copies; ++c) {
    TriangleMeshDesc placed = grid;
    placed.transform = TransformDesc{};
    placed.transform->translate = {0.0, -0.5 + 0.6 * c, 0.0};
    scene.meshes.push_back(placed);
  }
  scene.spheres.push_back(SphereDesc{.center = {0.5, 0.4, 0.2}, .radius = 0.3});
  SphereDesc lamp{.center = {0.0, 2.5, 1.0}, .radius = 0.4};
  lamp.material = 1;
  scene.spheres.push_back(lamp);
  shrink(scene.render);
  return scene;
}

TEST(DeviceLayout, MeshTrianglesJoinTheDeviceBvh) {
  const auto scene = PreparedScene::build(mesh_scene(1));
  ASSERT_NE(scene->view().bvh.triangles, nullptr) << "the CPU should trace the mesh apart";
  expect_same_image(*scene, "one mesh");
}

TEST(DeviceLayout, SharedMeshesAreBakedForTheDevice) {
  SceneDescription description = mesh_scene(3);
  // Vertex normals of the height field, and placements turned and stretched, so that the
  // baked normals go through each placement's inverse transpose.
  for (std::size_t m = 0; m < description.meshes.size(); ++m) {
    TriangleMeshDesc& mesh = description.meshes[m];
    mesh.normals.clear();
    for (const dvec3& p : mesh.positions)
      mesh.normals.push_back(
          glm::normalize(dvec3(-0.6 * std::cos(3.0 * p.x) * std::cos(2.0 * p.z), 1.0,
                               0.4 * std::sin(3.0 * p.x) * std::sin(2.0 * p.z))));
    mesh.transform->rotate_axis = {0.2, 1.0, 0.1};
    mesh.transform->rotate_degrees = 35.0 * static_cast<double>(m);
    mesh.transform->scale = {1.0 + 0.3 * static_cast<double>(m), 1.0, 0.8};
  }
  const auto shared = PreparedScene::build(description);
  ASSERT_EQ(shared->shared_mesh_placements(), 3u);
  const DeviceSceneSource& source = shared->device_source();
  ASSERT_EQ(source.unsupported, "");
  EXPECT_EQ(source.view.bvh.instances, nullptr);
  EXPECT_EQ(source.view.mesh_placement_count, 0u);
  // The two spheres in the shape BVH, and each placement's 1,152 triangles of its own.
  ASSERT_EQ(source.bvh.primitives.size(), 2u + 3u * 1152u);
  ASSERT_EQ(source.triangles.size(), 3u * 1152u);
  for (std::uint32_t reference : source.bvh.primitives) {
    if (primitive_type(reference) == PrimitiveType::kTriangle) {
      ASSERT_LT(primitive_index(reference), source.triangles.size());
    }
  }
  // The placements' triangles are intersected in world space here and in object space on
  // the CPU, so hits differ in their last bits and a path near a silhouette may take
  // another turn: pixels agree to within float rounding but for a few, and the means agree.
  const Comparison c = compare_layouts(*shared);
  EXPECT_LE(c.far_apart, c.pixels / 50) << c.far_apart << " of " << c.pixels << " pixels";
  EXPECT_NEAR(c.mean_device, c.mean_cpu, 0.01 * c.mean_cpu);
  EXPECT_GT(c.mean_cpu, 0.0);

  // Baked on the CPU too (instancing off), the scene renders through its layout as there.
  PrepareOptions bake;
  bake.instancing = false;
  expect_same_image(*PreparedScene::build(description, bake), "baked placements");
}

TEST(DeviceLayout, BakedPlacementsCarryTheirTransformNormalsAndMaterial) {
  // Two geometries back to back (one triangle, then two), the first placed twice.
  const std::vector<Triangle> object = {Triangle{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), 0},
                                        Triangle{vec3(0, 0, 0), vec3(0, 0, 1), vec3(1, 0, 0), 0},
                                        Triangle{vec3(1, 0, 0), vec3(0, 0, 1), vec3(1, 0, 1), 0}};
  std::vector<TriangleAttributes> attributes(3);
  for (TriangleAttributes& a : attributes)
    a = TriangleAttributes{vec3(0, 0, 1), glm::normalize(vec3(1, 0, 1)),
                           vec3(0),       vec2(0.25f, 0.5f),
                           vec2(1, 0),    vec2(0, 1)};
  const auto placement = [](std::uint32_t first_triangle, std::uint32_t material,
                            const AffineTransform& to_world) {
    MeshPlacement p;
    p.first_triangle = first_triangle;
    p.material = material;
    p.object_to_world = to_world;
    p.world_to_object = to_world.inverse();
    return p;
  };
  AffineTransform moved;
  moved.translation = dvec3(10.0, 0.0, 0.0);
  AffineTransform turned;  // a quarter turn about y, scaled by 2 along x first
  turned.linear = glm::dmat3(dvec3(0, 0, -2), dvec3(0, 1, 0), dvec3(1, 0, 0));
  const std::vector<MeshPlacement> placements = {placement(0, 4, moved), placement(1, 5, moved),
                                                 placement(0, 6, turned)};
  EXPECT_EQ(baked_placement_triangles(placements, object.size()), 1u + 2u + 1u);

  const BakedPlacements baked = bake_placements(placements, object, attributes);
  ASSERT_EQ(baked.triangles.size(), 4u);
  ASSERT_EQ(baked.attributes.size(), 4u);
  EXPECT_EQ(baked.triangles[0].p1, vec3(11, 0, 0));
  EXPECT_EQ(baked.triangles[0].material, 4u);
  EXPECT_EQ(baked.triangles[1].p1, vec3(10, 0, 1));  // the second geometry's first
  EXPECT_EQ(baked.triangles[2].p2, vec3(11, 0, 1));
  EXPECT_EQ(baked.triangles[2].material, 5u);
  EXPECT_EQ(baked.triangles[3].p1, vec3(0, 0, -2));  // x = (1, 0, 0) goes to (0, 0, -2)
  EXPECT_EQ(baked.triangles[3].material, 6u);
  // A normal stays perpendicular to the placed surface: n1 = (1, 0, 1) / sqrt(2) to the
  // placed images of its tangents (0, 1, 0) and (1, 0, -1), which the stretch along x
  // would tilt it against if it were placed as a direction; and it stays unit length.
  const dvec3 n1 = dvec3(baked.attributes[3].n1);
  EXPECT_NEAR(glm::dot(n1, turned.vector(dvec3(0, 1, 0))), 0.0, 1e-6);
  EXPECT_NEAR(glm::dot(n1, turned.vector(dvec3(1, 0, -1))), 0.0, 1e-6);
  EXPECT_NEAR(glm::length(n1), 1.0, 1e-6);
  EXPECT_NEAR(baked.attributes[3].n0.x, 1.0f, 1e-6f);  // (0, 0, 1) goes to x
  EXPECT_EQ(baked.attributes[3].n2, vec3(0.0f));       // none stored stays none
  EXPECT_EQ(baked.attributes[3].uv0, vec2(0.25f, 0.5f));
  EXPECT_TRUE(bake_placements(placements, object, {}).attributes.empty());
}

TEST(DeviceLayout, BakingPlacementsIsBounded) {
  EXPECT_EQ(baked_placements_refusal(1000, 500, 1000), "");
  const std::string over = baked_placements_refusal(1001, 500, 1000);
  EXPECT_NE(over.find("1001 triangles"), std::string::npos) << over;
  EXPECT_NE(over.find("limit of 1000"), std::string::npos) << over;
  const std::string references =
      baked_placements_refusal(std::size_t{1} << 26, std::size_t{1} << 26, std::size_t{1} << 30);
  EXPECT_EQ(references, "");
  EXPECT_NE(baked_placements_refusal((std::size_t{1} << 26) + 1, std::size_t{1} << 26,
                                     std::size_t{1} << 30)
                .find("primitive reference"),
            std::string::npos);
  EXPECT_EQ(baked_placements_refusal(kMaxDeviceBakedTriangles, 0), "");
  EXPECT_NE(baked_placements_refusal(kMaxDeviceBakedTriangles + 1, 0), "");
}

TEST(DeviceLayout, BuffersCoverEveryArrayTheViewPointsTo) {
  LoadedScene loaded = load_scene_file(kExamples / "textures.yaml");
  shrink(loaded.scene.render);
  const auto scene = PreparedScene::build(loaded.scene);
  const DeviceSceneSource& source = scene->device_source();
  // Pointing every field at a copy must move every pointer the device reads: copy each
  // buffer, assign, and check that no pointer into the host arrays is left.
  std::vector<std::vector<unsigned char>> copies;
  SceneView moved = source.view;
  for (const DeviceBuffer& b : source.buffers) {
    ASSERT_GT(b.bytes, 0u);
    ASSERT_NE(b.assign, nullptr);
    const auto* bytes = static_cast<const unsigned char*>(b.host);
    copies.emplace_back(bytes, bytes + b.bytes);
    b.assign(moved, copies.back().data());
  }
  EXPECT_NE(moved.materials, source.view.materials);
  EXPECT_NE(moved.bvh.nodes, source.view.bvh.nodes);
  EXPECT_NE(moved.bvh.primitives, source.view.bvh.primitives);
  EXPECT_NE(moved.bvh.compressed_nodes, source.view.bvh.compressed_nodes);
  EXPECT_NE(moved.bvh.compressed_primitives, source.view.bvh.compressed_primitives);
  EXPECT_NE(moved.textures, source.view.textures);
  EXPECT_NE(moved.texels, source.view.texels);
  EXPECT_GT(source.bytes(), 0u);
}

TEST(DeviceLayout, RayonScenesRenderAsOnTheCpu) {
  std::vector<std::filesystem::path> scenes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(kRayonDir, ec))
    if (entry.path().extension() == ".yaml") scenes.push_back(entry.path());
  if (scenes.empty()) GTEST_SKIP() << "no RayON scenes in " << kRayonDir;
  std::sort(scenes.begin(), scenes.end());
  int compared = 0;
  for (const auto& path : scenes) {
    LoadedScene loaded;
    try {
      loaded = load_scene_file(path);
    } catch (const SceneError&) {
      continue;  // the scene whose model is not shipped (rayon_scenes_test.cpp checks it)
    }
    shrink(loaded.scene.render);
    PrepareOptions bake;
    bake.instancing = false;
    const auto scene = PreparedScene::build(loaded.scene, bake);
    if (!scene->device_source().unsupported.empty()) continue;
    expect_same_image(*scene, path.filename().string());
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

}  // namespace
}  // namespace tessera
