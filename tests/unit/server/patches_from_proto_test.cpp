// B-spline/NURBS patches and trimmed faces in scene.proto: each converts to the
// description, and bad grids, knots, weights and loops are named by their protobuf path.
#include <gtest/gtest.h>

#include "convert/scene_proto.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::set_vec3;
using testing::tiny_scene;
using testing::tiny_settings;

// A flat 4 x 4 grid over [0, 3]^2 at z = 0.
void fill_grid(v1::SplinePatch* p) {
  p->set_count_u(4);
  p->set_count_v(4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      p->add_control_points(i);
      p->add_control_points(j);
      p->add_control_points(0.0);
    }
}

void add_loop(v1::TrimmedFace* face, std::initializer_list<double> uv) {
  v1::UvLoop* loop = face->add_loops();
  for (double value : uv) loop->add_uv(value);
}

// tiny_scene plus one geometry entry (geometry[2]) with material "grey".
v1::Geometry* add_geometry(v1::Scene& scene) {
  v1::Geometry* g = scene.add_geometry();
  g->set_material("grey");
  return g;
}

void expect_first_issue(const v1::Scene& scene, const std::string& field,
                        const std::string& message) {
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_FALSE(conversion.ok());
  EXPECT_EQ(conversion.issues[0].field, field) << describe_issues(conversion.issues);
  EXPECT_NE(conversion.issues[0].message.find(message), std::string::npos)
      << "message was: " << conversion.issues[0].message;
}

TEST(PatchesFromProto, ConvertsAPatchAndATrimmedFace) {
  v1::Scene scene = tiny_scene();
  v1::SplinePatch* patch = add_geometry(scene)->mutable_spline_patch();
  fill_grid(patch);
  for (int i = 0; i < 16; ++i) patch->add_weights(1.0 + i % 2);
  for (double k : {0, 0, 0, 0, 1, 1, 1, 1}) patch->add_knots_u(k);
  v1::Geometry* g = add_geometry(scene);
  v1::TrimmedFace* face = g->mutable_trimmed_face();
  face->mutable_sphere()->set_radius(2.0);
  add_loop(face, {0, 0.1, 0.5, 0.1, 0.5, 0.9});
  add_loop(face, {0.2, 0.3, 0.3, 0.3, 0.3, 0.4});
  set_vec3(g->mutable_transform()->mutable_translate(), 1, 2, 3);

  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_TRUE(conversion.ok()) << describe_issues(conversion.issues);
  const SceneDescription& d = *conversion.scene;
  ASSERT_EQ(d.patches.size(), 1u);
  EXPECT_EQ(d.patches[0].count_u, 4u);
  ASSERT_EQ(d.patches[0].control_points.size(), 16u);
  EXPECT_EQ(d.patches[0].control_points[6], glm::dvec3(1, 2, 0));
  EXPECT_EQ(d.patches[0].weights[1], 2.0);
  EXPECT_EQ(d.patches[0].knots_u.size(), 8u);
  EXPECT_TRUE(d.patches[0].knots_v.empty());
  EXPECT_EQ(d.patches[0].source_index, 2u);
  ASSERT_EQ(d.trimmed_faces.size(), 1u);
  const auto* sphere = std::get_if<SphereDesc>(&d.trimmed_faces[0].surface);
  ASSERT_NE(sphere, nullptr);
  EXPECT_EQ(sphere->radius, 2.0);
  ASSERT_EQ(d.trimmed_faces[0].loops.size(), 2u);
  EXPECT_EQ(d.trimmed_faces[0].loops[1][2], glm::dvec2(0.3, 0.4));
  ASSERT_TRUE(d.trimmed_faces[0].transform.has_value());
  EXPECT_EQ(d.trimmed_faces[0].transform->translate, glm::dvec3(1, 2, 3));
}

TEST(PatchesFromProto, BadKnotIsNamedByItsProtoPath) {
  v1::Scene scene = tiny_scene();
  v1::SplinePatch* patch = add_geometry(scene)->mutable_spline_patch();
  fill_grid(patch);
  for (double k : {0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 1.0, 1.0}) patch->add_knots_v(k);
  expect_first_issue(scene, "geometry[2].spline_patch.knots_v[5]", "non-decreasing");
}

TEST(PatchesFromProto, BadWeightAndRaggedPointsAreNamed) {
  v1::Scene scene = tiny_scene();
  v1::SplinePatch* patch = add_geometry(scene)->mutable_spline_patch();
  fill_grid(patch);
  for (int i = 0; i < 16; ++i) patch->add_weights(i == 7 ? -1.0 : 1.0);
  expect_first_issue(scene, "geometry[2].spline_patch.weights[7]", "> 0");

  scene = tiny_scene();
  patch = add_geometry(scene)->mutable_spline_patch();
  fill_grid(patch);
  patch->add_control_points(1.0);
  expect_first_issue(scene, "geometry[2].spline_patch.control_points", "multiple of 3");

  // Counts that do not match the points sent are refused before anything is built.
  scene = tiny_scene();
  patch = add_geometry(scene)->mutable_spline_patch();
  fill_grid(patch);
  patch->set_count_u(100000);
  expect_first_issue(scene, "geometry[2].spline_patch.control_points",
                     "must have count_u * count_v = 400000 points, got 16");
}

TEST(PatchesFromProto, LoopsAndSurfacesOfTrimmedFacesAreNamed) {
  v1::Scene scene = tiny_scene();
  v1::TrimmedFace* face = add_geometry(scene)->mutable_trimmed_face();
  face->mutable_sphere()->set_radius(1.0);
  add_loop(face, {0, 0.1, 0.5, 0.1, 0.5, 0.9});
  add_loop(face, {0.2, 0.3, 0.3, 0.3});
  expect_first_issue(scene, "geometry[2].trimmed_face.loops[1]", "at least 3 points");

  scene = tiny_scene();
  face = add_geometry(scene)->mutable_trimmed_face();
  face->mutable_torus()->mutable_axis();  // set, all zero (unset would be the default +y)
  face->mutable_torus()->set_major_radius(1.0);
  face->mutable_torus()->set_minor_radius(0.2);
  add_loop(face, {0, 0.1, 0.5, 0.1, 0.5, 0.9});
  expect_first_issue(scene, "geometry[2].trimmed_face.torus.axis", "zero vector");

  scene = tiny_scene();
  face = add_geometry(scene)->mutable_trimmed_face();
  fill_grid(face->mutable_patch());
  face->mutable_patch()->set_count_v(3);
  add_loop(face, {0, 0.1, 0.5, 0.1, 0.5, 0.9});
  expect_first_issue(scene, "geometry[2].trimmed_face.patch.count_v", "at least 4");

  scene = tiny_scene();
  face = add_geometry(scene)->mutable_trimmed_face();
  add_loop(face, {0, 0.1, 0.5, 0.1, 0.5, 0.9});
  expect_first_issue(scene, "geometry[2].trimmed_face.surface", "is required");
}

}  // namespace
}  // namespace tessera::server
