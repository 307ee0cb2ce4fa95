// YAML for B-spline/NURBS patches and trimmed faces: every field is read, defaults are the
// documented ones, and bad control grids, knots, weights and loops name file, line and field.
#include <gtest/gtest.h>

#include <string>

#include "scene_error_of.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "patches.yaml", ".");
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

// A 4 x 4 planar grid over [0, 3]^2 in z = 0, written row by row (rows along u).
const char* kGrid =
    "[[[0,0,0],[0,1,0],[0,2,0],[0,3,0]],\n"
    "                     [[1,0,0],[1,1,0],[1,2,0],[1,3,0]],\n"
    "                     [[2,0,0],[2,1,0],[2,2,0],[2,3,0]],\n"
    "                     [[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]";

std::string with_geometry(const std::string& entry) {
  return "materials:\n"
         "  - { name: white, type: lambertian }\n"
         "geometry:\n"
         "  - { type: sphere, material: white, center: [0, 0, -9], radius: 1 }\n" +
         entry + "\n";
}

TEST(YamlPatches, ReadsAPatchWithDefaultKnots) {
  const LoadedScene loaded = load(with_geometry(std::string("  - type: bspline_patch\n"
                                                            "    material: white\n"
                                                            "    control_points: ") +
                                                kGrid + "\n"));
  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(loaded.scene.patches.size(), 1u);
  const SplinePatchDesc& p = loaded.scene.patches[0];
  EXPECT_EQ(p.count_u, 4u);
  EXPECT_EQ(p.count_v, 4u);
  ASSERT_EQ(p.control_points.size(), 16u);
  EXPECT_EQ(p.control_points[1], glm::dvec3(0, 1, 0));  // row 0, point 1: index i * count_v + j
  EXPECT_EQ(p.control_points[4], glm::dvec3(1, 0, 0));
  EXPECT_TRUE(p.weights.empty());
  EXPECT_TRUE(p.knots_u.empty());
  EXPECT_EQ(p.source_index, 1u);
  EXPECT_EQ(clamped_uniform_knots(4), (std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(clamped_uniform_knots(6),
            (std::vector<double>{0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1}));
}

TEST(YamlPatches, ReadsWeightsKnotsAndTransform) {
  const LoadedScene loaded =
      load(with_geometry(std::string("  - type: bspline_patch\n"
                                     "    material: white\n"
                                     "    control_points: ") +
                         kGrid + "\n" +
                         "    weights: [[1,1,1,1],[1,2,2,1],[1,2,2,1],[1,1,1,1]]\n"
                         "    knots_u: [0, 0, 0, 0, 2, 2, 2, 2]\n"
                         "    knots_v: [-1, -1, -1, -1, 1, 1, 1, 1]\n"
                         "    transform: { translate: [0, 0, 1] }\n"));
  const SplinePatchDesc& p = loaded.scene.patches.at(0);
  EXPECT_EQ(p.weights.size(), 16u);
  EXPECT_EQ(p.weights[5], 2.0);
  EXPECT_EQ(p.knots_u[4], 2.0);
  EXPECT_EQ(p.knots_v[0], -1.0);
  ASSERT_TRUE(p.transform.has_value());
  EXPECT_EQ(p.transform->translate, glm::dvec3(0, 0, 1));
}

TEST(YamlPatches, ReadsTrimmedFacesOfEverySurfaceKind) {
  const LoadedScene loaded = load(with_geometry(
      std::string("  - type: trimmed\n"
                  "    material: white\n"
                  "    surface: { type: sphere, center: [0, 0, 0], radius: 2 }\n"
                  "    loops: [[[0, 0.2], [0.5, 0.2], [0.5, 0.8], [0, 0.8]], [[0.1, 0.4], [0.2, "
                  "0.4], [0.2, 0.5]]]\n"
                  "  - type: trimmed\n"
                  "    material: white\n"
                  "    surface: { type: plane, point: [0, 1, 0], normal: [0, 1, 0] }\n"
                  "    loops: [[[-1, -1], [1, -1], [0, 1]]]\n"
                  "    transform: { rotate: { axis: [1, 0, 0], degrees: 30 } }\n"
                  "  - type: trimmed\n"
                  "    material: white\n"
                  "    surface: { type: cylinder, base: [0, 0, 0], radius: 1, height: 2 }\n"
                  "    loops: [[[0.9, 0], [1.1, 0], [1.1, 1], [0.9, 1]]]\n"
                  "  - type: trimmed\n"
                  "    material: white\n"
                  "    surface:\n"
                  "      type: bspline_patch\n"
                  "      control_points: ") +
      kGrid + "\n" + "    loops: [[[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]]]\n"));
  EXPECT_TRUE(loaded.warnings.empty());
  const auto& faces = loaded.scene.trimmed_faces;
  ASSERT_EQ(faces.size(), 4u);
  const auto* sphere = std::get_if<SphereDesc>(&faces[0].surface);
  ASSERT_NE(sphere, nullptr);
  EXPECT_EQ(sphere->radius, 2.0);
  ASSERT_EQ(faces[0].loops.size(), 2u);
  EXPECT_EQ(faces[0].loops[1][2], glm::dvec2(0.2, 0.5));
  EXPECT_EQ(faces[0].source_index, 1u);
  ASSERT_NE(std::get_if<PlaneDesc>(&faces[1].surface), nullptr);
  EXPECT_TRUE(faces[1].transform.has_value());
  EXPECT_NE(std::get_if<CylinderDesc>(&faces[2].surface), nullptr);
  const auto* patch = std::get_if<SplinePatchDesc>(&faces[3].surface);
  ASSERT_NE(patch, nullptr);
  EXPECT_EQ(patch->control_points.size(), 16u);
  EXPECT_STREQ(trimmed_surface_name(faces[3].surface), "bspline_patch");
}

TEST(YamlPatches, BadKnotsNameTheKnotAndItsLine) {
  const SceneIssue issue = load_error(with_geometry(std::string("  - type: bspline_patch\n"
                                                                "    material: white\n"
                                                                "    control_points: ") +
                                                    kGrid + "\n" +
                                                    "    knots_u: [0, 0, 0, 0,\n"
                                                    "              1, 0.5, 1, 1]\n"));
  EXPECT_EQ(issue.file, "patches.yaml");
  EXPECT_EQ(issue.field, "geometry[1].knots_u[5]");
  EXPECT_NE(issue.message.find("non-decreasing"), std::string::npos) << issue.message;
  EXPECT_EQ(issue.line, 12);
}

TEST(YamlPatches, WrongKnotCountIsRefused) {
  const SceneIssue issue =
      load_error(with_geometry(std::string("  - type: bspline_patch\n"
                                           "    material: white\n"
                                           "    control_points: ") +
                               kGrid + "\n" + "    knots_v: [0, 0, 0, 1, 1, 1]\n"));
  EXPECT_EQ(issue.field, "geometry[1].knots_v");
  EXPECT_NE(issue.message.find("must have 8 values"), std::string::npos) << issue.message;
  EXPECT_EQ(issue.line, 11);
}

TEST(YamlPatches, NonPositiveWeightNamesTheWeight) {
  const SceneIssue issue = load_error(with_geometry(std::string("  - type: bspline_patch\n"
                                                                "    material: white\n"
                                                                "    control_points: ") +
                                                    kGrid + "\n" +
                                                    "    weights: [[1,1,1,1],[1,1,1,1],\n"
                                                    "              [1,1,0,1],[1,1,1,1]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].weights[10]");
  EXPECT_NE(issue.message.find("> 0"), std::string::npos) << issue.message;
  EXPECT_EQ(issue.line, 12);
}

TEST(YamlPatches, RaggedOrShortGridsAreRefused) {
  SceneIssue issue =
      load_error(with_geometry("  - type: bspline_patch\n"
                               "    material: white\n"
                               "    control_points: [[[0,0,0],[0,1,0],[0,2,0],[0,3,0]],\n"
                               "                     [[1,0,0],[1,1,0],[1,2,0],[1,3,0],[1,4,0]],\n"
                               "                     [[2,0,0],[2,1,0],[2,2,0],[2,3,0]],\n"
                               "                     [[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].control_points[1]");
  EXPECT_EQ(issue.line, 8);
  issue =
      load_error(with_geometry("  - type: bspline_patch\n"
                               "    material: white\n"
                               "    control_points: [[[0,0,0],[0,1,0],[0,2,0],[0,3,0]]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].control_points");
  EXPECT_NE(issue.message.find("at least 4 rows"), std::string::npos);
}

TEST(YamlPatches, ShortLoopNamesTheLoopAndItsLine) {
  const SceneIssue issue = load_error(
      with_geometry("  - type: trimmed\n"
                    "    material: white\n"
                    "    surface: { type: disk, center: [0, 0, 0], normal: [0, 0, 1], radius: 1 }\n"
                    "    loops:\n"
                    "      - [[0, 0.1], [0.5, 0.1], [0.5, 0.9]]\n"
                    "      - [[0.1, 0.2], [0.2, 0.2]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].loops[1]");
  EXPECT_NE(issue.message.find("at least 3 points"), std::string::npos) << issue.message;
  EXPECT_EQ(issue.line, 10);
}

TEST(YamlPatches, DegenerateOuterLoopAndBadSurfaceAreRefused) {
  SceneIssue issue = load_error(
      with_geometry("  - type: trimmed\n"
                    "    material: white\n"
                    "    surface: { type: quad, corner: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0] }\n"
                    "    loops: [[[0, 0], [0.5, 0.5], [1, 1]]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].loops[0]");
  EXPECT_NE(issue.message.find("no area"), std::string::npos) << issue.message;
  EXPECT_EQ(issue.line, 8);

  issue = load_error(with_geometry(
      "  - type: trimmed\n"
      "    material: white\n"
      "    surface: { type: torus, center: [0, 0, 0], major_radius: 1, minor_radius: -1 }\n"
      "    loops: [[[0, 0], [0.5, 0], [0.5, 0.5]]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].surface.minor_radius");
  EXPECT_EQ(issue.line, 7);

  issue =
      load_error(with_geometry("  - type: trimmed\n"
                               "    material: white\n"
                               "    surface: { type: sdf_box, half_extent: [1, 1, 1] }\n"
                               "    loops: [[[0, 0], [0.5, 0], [0.5, 0.5]]]\n"));
  EXPECT_EQ(issue.field, "geometry[1].surface.type");
}

TEST(YamlPatches, LoopsGoingAllTheWayRoundAWrappingDirectionAreRefused) {
  // u wraps on a cylinder: 0 -> 0.4 -> 0.8 -> 0.2 (taken as 1.2) does not close.
  const std::string loop = "    loops: [[[0, 0.2], [0.4, 0.2], [0.8, 0.2], [0.2, 0.8]]]\n";
  const SceneIssue issue = load_error(
      with_geometry("  - type: trimmed\n"
                    "    material: white\n"
                    "    surface: { type: cylinder, base: [0, 0, 0], radius: 1, height: 2 }\n" +
                    loop));
  EXPECT_EQ(issue.field, "geometry[1].loops[0]");
  EXPECT_NE(issue.message.find("all the way round"), std::string::npos) << issue.message;
  // The same loop on a rectangle, whose uv does not wrap, is an ordinary quadrilateral.
  EXPECT_NO_THROW(load(with_geometry(
      "  - type: trimmed\n"
      "    material: white\n"
      "    surface: { type: rectangle, corner: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0] }\n" +
      loop)));
}

TEST(YamlPatches, PatchSizesAreBoundedByTheLimits) {
  SceneLoadOptions options;
  options.limits.max_patch_control_points = 20;
  std::string two = with_geometry(
      std::string("  - { type: bspline_patch, material: white, control_points: ") + kGrid +
      " }\n  - { type: bspline_patch, material: white, control_points: " + kGrid + " }");
  try {
    load_scene_yaml(two, "patches.yaml", ".", options);
    ADD_FAILURE() << "expected the control point limit to refuse the scene";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.issue().field, "geometry");
    EXPECT_NE(e.issue().message.find("patch control points"), std::string::npos);
  }
  options = {};
  options.limits.max_trim_points = 5;
  try {
    load_scene_yaml(with_geometry("  - { type: trimmed, material: white, surface: { type: sphere, "
                                  "center: [0,0,0], radius: 1 }, loops: [[[0,0],[1,0],[1,1]], "
                                  "[[0.1,0.1],[0.2,0.1],[0.2,0.2]]] }"),
                    "patches.yaml", ".", options);
    ADD_FAILURE() << "expected the trim point limit to refuse the scene";
  } catch (const SceneError& e) {
    EXPECT_NE(e.issue().message.find("trimming loop points"), std::string::npos);
  }
}

}  // namespace
}  // namespace tessera
