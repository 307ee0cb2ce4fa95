// YAML for the analytic and signed-distance shapes and per-geometry transforms: every field
// is read, defaults are the documented ones, and bad values name file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene_error_of.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "shapes.yaml", ".");
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

// The entry is on line 5 of the text this returns.
std::string with_geometry(const std::string& entry) {
  return "materials:\n"
         "  - { name: white, type: lambertian }\n"
         "  - { name: lamp, type: light, emission: 3 }\n"
         "geometry:\n"
         "  - " +
         entry + "\n";
}

TEST(YamlShapes, ReadsEveryShapeType) {
  const LoadedScene loaded = load(R"(
materials:
  - { name: white, type: lambertian }
geometry:
  - { type: plane, material: white, point: [0, -1, 0], normal: [0, 2, 0] }
  - { type: disk, material: white, center: [1, 2, 3], normal: [0, 0, 1], radius: 2, inner_radius: 0.5 }
  - { type: cylinder, material: white, base: [0, 0, 0], axis: [1, 0, 0], radius: 0.5, height: 2, caps: true }
  - { type: cone, material: white, base: [0, 1, 0], base_radius: 1, top_radius: 0.25, height: 3 }
  - { type: torus, material: white, center: [0, 0, 1], major_radius: 2, minor_radius: 0.5 }
  - { type: sdf_box, material: white, center: [1, 1, 1], half_extent: [1, 2, 3] }
  - { type: sdf_rounded_box, material: white, half_extent: [1, 1, 1], rounding: 0.25 }
  - { type: sdf_torus, material: white, center: [0, 0, 0], axis: [0, 0, 1], major_radius: 1, minor_radius: 0.3 }
  - { type: sdf_capsule, material: white, a: [0, 0, 0], b: [0, 2, 0], radius: 0.5, visible: false }
)");
  EXPECT_TRUE(loaded.warnings.empty());
  const SceneDescription& s = loaded.scene;
  ASSERT_EQ(s.planes.size(), 1u);
  EXPECT_EQ(s.planes[0].point, glm::dvec3(0, -1, 0));
  EXPECT_EQ(s.planes[0].normal, glm::dvec3(0, 2, 0));
  EXPECT_EQ(s.planes[0].source_index, 0u);
  ASSERT_EQ(s.disks.size(), 1u);
  EXPECT_EQ(s.disks[0].center, glm::dvec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(s.disks[0].radius, 2.0);
  EXPECT_DOUBLE_EQ(s.disks[0].inner_radius, 0.5);
  ASSERT_EQ(s.cylinders.size(), 1u);
  EXPECT_EQ(s.cylinders[0].axis, glm::dvec3(1, 0, 0));
  EXPECT_DOUBLE_EQ(s.cylinders[0].height, 2.0);
  EXPECT_TRUE(s.cylinders[0].caps);
  ASSERT_EQ(s.cones.size(), 1u);
  EXPECT_EQ(s.cones[0].axis, glm::dvec3(0, 1, 0));  // default axis
  EXPECT_DOUBLE_EQ(s.cones[0].top_radius, 0.25);
  EXPECT_FALSE(s.cones[0].caps);
  EXPECT_EQ(s.cones[0].source_index, 3u);
  ASSERT_EQ(s.tori.size(), 1u);
  EXPECT_DOUBLE_EQ(s.tori[0].minor_radius, 0.5);
  ASSERT_EQ(s.sdf_boxes.size(), 2u);
  EXPECT_EQ(s.sdf_boxes[0].half_extent, glm::dvec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(s.sdf_boxes[0].rounding, 0.0);
  EXPECT_EQ(s.sdf_boxes[1].center, glm::dvec3(0.0));
  EXPECT_DOUBLE_EQ(s.sdf_boxes[1].rounding, 0.25);
  EXPECT_EQ(s.sdf_boxes[1].source_index, 6u);
  ASSERT_EQ(s.sdf_tori.size(), 1u);
  EXPECT_EQ(s.sdf_tori[0].axis, glm::dvec3(0, 0, 1));
  ASSERT_EQ(s.sdf_capsules.size(), 1u);
  EXPECT_EQ(s.sdf_capsules[0].b, glm::dvec3(0, 2, 0));
  EXPECT_FALSE(s.sdf_capsules[0].visible);
  EXPECT_EQ(s.analytic_shape_count(), 9u);
}

TEST(YamlShapes, ReadsTransformsOnAnyGeometry) {
  const LoadedScene loaded = load(R"(
materials:
  - { name: white, type: lambertian }
geometry:
  - type: sphere
    material: white
    center: [0, 0, 0]
    radius: 1
    transform: { translate: [1, 2, 3], rotate: { axis: [0, 1, 0], degrees: 90 }, scale: [1, 2, 3] }
  - { type: triangle, material: white, v0: [0, 0, 0], v1: [1, 0, 0], v2: [0, 1, 0], transform: { scale: 2 } }
  - { type: cylinder, material: white, base: [0, 0, 0], radius: 1, height: 1 }
)");
  const SceneDescription& s = loaded.scene;
  ASSERT_TRUE(s.spheres[0].transform.has_value());
  const TransformDesc& t = *s.spheres[0].transform;
  EXPECT_EQ(t.translate, glm::dvec3(1, 2, 3));
  EXPECT_EQ(t.rotate_axis, glm::dvec3(0, 1, 0));
  EXPECT_DOUBLE_EQ(t.rotate_degrees, 90.0);
  EXPECT_EQ(t.scale, glm::dvec3(1, 2, 3));
  // Scale first, then rotate 90 degrees about y (x -> -z), then translate.
  const glm::dvec3 moved = glm::dvec3(t.matrix() * glm::dvec4(1, 0, 0, 1));
  EXPECT_NEAR(moved.x, 1.0, 1e-12);
  EXPECT_NEAR(moved.y, 2.0, 1e-12);
  EXPECT_NEAR(moved.z, 2.0, 1e-12);
  ASSERT_TRUE(s.meshes[0].transform.has_value());
  EXPECT_EQ(s.meshes[0].transform->scale, glm::dvec3(2.0));
  EXPECT_TRUE(s.meshes[0].transform->uniform_scale());
  EXPECT_FALSE(s.cylinders[0].transform.has_value());
}

TEST(YamlShapes, BadValuesNameFileLineAndField) {
  struct Case {
    std::string entry;
    std::string field;
    std::string message_part;
  };
  const Case cases[] = {
      {"{ type: cylinder, material: white, base: [0, 0, 0], radius: -1, height: 1 }",
       "geometry[0].radius", "must be > 0, got -1"},
      {"{ type: cylinder, material: white, base: [0, 0, 0], axis: [0, 0, 0], radius: 1, height: 1 "
       "}",
       "geometry[0].axis", "zero vector"},
      {"{ type: cone, material: white, base: [0, 0, 0], base_radius: 0, height: 1 }",
       "geometry[0].base_radius", "both be 0"},
      {"{ type: disk, material: white, center: [0, 0, 0], normal: [0, 1, 0], radius: 1, "
       "inner_radius: 1 }",
       "geometry[0].inner_radius", "[0, radius)"},
      {"{ type: torus, material: white, center: [0, 0, 0], major_radius: 1, minor_radius: 0 }",
       "geometry[0].minor_radius", "must be > 0"},
      {"{ type: sdf_torus, material: white, center: [0, 0, 0], major_radius: 1, minor_radius: 2 }",
       "geometry[0].minor_radius", "< major_radius"},
      {"{ type: sdf_rounded_box, material: white, half_extent: [1, 1, 0.5], rounding: 0.75 }",
       "geometry[0].rounding", "smallest half extent"},
      {"{ type: sdf_box, material: white, half_extent: [1, 0, 1] }", "geometry[0].half_extent",
       "> 0"},
      {"{ type: sdf_capsule, material: white, a: [0, 0, 0], b: [0, 1, 0], radius: .nan }",
       "geometry[0].radius", "finite"},
      {"{ type: plane, material: white, normal: [0, 0, 0] }", "geometry[0].normal", "zero vector"},
      {"{ type: plane, material: lamp, normal: [0, 1, 0] }", "geometry[0].material", "cannot emit"},
      {"{ type: sphere, material: white, center: [0, 0, 0], radius: 1, transform: { scale: [1, 0, "
       "1] } }",
       "geometry[0].transform.scale", "singular"},
      {"{ type: sphere, material: white, center: [0, 0, 0], radius: 1, transform: { rotate: { "
       "axis: [0, 0, 0], degrees: 10 } } }",
       "geometry[0].transform.rotate.axis", "zero vector"},
      {"{ type: sphere, material: white, center: [0, 0, 0], radius: 1, transform: { rotate: { "
       "axis: [0, 1, 0] } } }",
       "geometry[0].transform.rotate.degrees", "required"},
      {"{ type: cylinder, material: white, base: [0, 0, 0], radius: 1 }", "geometry[0].height",
       "required"},
      {"{ type: disk, material: white, center: [0, 0], normal: [0, 1, 0], radius: 1 }",
       "geometry[0].center", "three numbers"},
      {"{ type: cone, material: white, base: [0, 0, 0], base_radius: 1, height: 1, caps: maybe }",
       "geometry[0].caps", "true or false"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.entry);
    const SceneIssue issue = load_error(with_geometry(c.entry));
    EXPECT_EQ(issue.file, "shapes.yaml");
    EXPECT_EQ(issue.line, 5);
    EXPECT_EQ(issue.field, c.field);
    EXPECT_NE(issue.message.find(c.message_part), std::string::npos) << issue.to_string();
  }
}

TEST(YamlShapes, ErrorsInsideABlockTransformPointAtTheirLine) {
  const SceneIssue issue = load_error(R"(materials:
  - { name: white, type: lambertian }
geometry:
  - type: sdf_box
    material: white
    half_extent: [1, 1, 1]
    transform:
      translate: [0, 0, 0]
      scale: [2, 2, 0]
)");
  EXPECT_EQ(issue.field, "geometry[0].transform.scale");
  EXPECT_EQ(issue.line, 9);
  EXPECT_EQ(issue.to_string().rfind("shapes.yaml:9: geometry[0].transform.scale: ", 0), 0u)
      << issue.to_string();
}

TEST(YamlShapes, UnknownKeysOfNewShapesAreErrorsOrLenientWarnings) {
  const std::string text = with_geometry(
      "{ type: disk, material: white, center: [0, 0, 0], normal: [0, 1, 0], radius: 1, "
      "height: 3, transform: { shear: 1 } }");
  const SceneIssue issue = test::scene_error_of([&] { load(text); }, text);
  EXPECT_EQ(issue.field, "geometry[0].height");
  SceneLoadOptions lenient;
  lenient.lenient = true;
  const LoadedScene loaded = load_scene_yaml(text, "shapes.yaml", ".", lenient);
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_EQ(loaded.warnings[0].field, "geometry[0].height");
  EXPECT_EQ(loaded.warnings[1].field, "geometry[0].transform.shear");
}

// A mesh file placed by RayON's position/scale keys: positions scaled and moved, normals
// mapped by the inverse transpose (a normal (1, 1, 0)/sqrt 2 under scale (2, 1, 1) becomes
// (1, 2, 0)/sqrt 5, not the scaled (2, 1, 0)/sqrt 5).
TEST(YamlShapes, ScaledMeshNormalsFollowTheInverseTranspose) {
  const auto dir = std::filesystem::temp_directory_path() / "tessera_yaml_shapes_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir / "slanted.obj");
    obj << "v 0 0 0\nv 1 -1 0\nv 0 0 1\n"
           "vn 0.70710678 0.70710678 0\nvn 0.70710678 0.70710678 0\nvn 0.70710678 0.70710678 0\n"
           "f 1//1 2//2 3//3\n";
  }
  const LoadedScene loaded = load_scene_yaml(
      with_geometry("{ type: obj, material: white, file: slanted.obj, position: [0, 0, 5], "
                    "scale: [2, 1, 1] }"),
      "shapes.yaml", dir);
  std::filesystem::remove_all(dir);
  // RayON's placement is kept as the entry's transform (entries of one file then share
  // geometry); placing the mesh by it maps normals by the inverse transpose.
  const TriangleMeshDesc& entry = loaded.scene.meshes.at(0);
  ASSERT_TRUE(entry.transform.has_value());
  const TriangleMeshDesc mesh = transformed_mesh(entry, *entry.transform);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  const glm::dvec3 expected = glm::normalize(glm::dvec3(1, 2, 0));
  for (std::size_t v = 0; v < mesh.normals.size(); ++v) {
    EXPECT_NEAR(mesh.normals[v].x, expected.x, 1e-7);
    EXPECT_NEAR(mesh.normals[v].y, expected.y, 1e-7);
    EXPECT_NEAR(mesh.normals[v].z, 0.0, 1e-7);
  }
  // The mapped normal is still perpendicular to the mapped triangle.
  const glm::dvec3 face =
      glm::cross(mesh.positions[mesh.indices[1]] - mesh.positions[mesh.indices[0]],
                 mesh.positions[mesh.indices[2]] - mesh.positions[mesh.indices[0]]);
  EXPECT_NEAR(std::fabs(glm::dot(glm::normalize(face), expected)), 1.0, 1e-9);
}

TEST(YamlShapes, ExampleShapesSceneLoads) {
  const auto path = std::filesystem::path(TESSERA_SOURCE_DIR) / "examples/scenes/shapes.yaml";
  const LoadedScene loaded = load_scene_file(path);
  EXPECT_TRUE(loaded.warnings.empty());
  const SceneDescription& s = loaded.scene;
  EXPECT_FALSE(s.planes.empty());
  EXPECT_FALSE(s.disks.empty());
  EXPECT_FALSE(s.cylinders.empty());
  EXPECT_FALSE(s.cones.empty());
  EXPECT_FALSE(s.tori.empty());
  EXPECT_GE(s.sdf_boxes.size(), 2u);
  EXPECT_FALSE(s.sdf_tori.empty());
  EXPECT_FALSE(s.sdf_capsules.empty());
}

}  // namespace
}  // namespace tessera
