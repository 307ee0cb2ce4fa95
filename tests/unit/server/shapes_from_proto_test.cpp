// The analytic and signed-distance shapes, transforms and mesh attributes of scene.proto:
// each converts to the description, and each bad value is named by its protobuf path.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "convert/scene_proto.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::set_vec3;
using testing::tiny_scene;
using testing::tiny_settings;

// tiny_scene plus one geometry entry (geometry[2]) with material "grey".
v1::Scene with_shape(void (*fill)(v1::Geometry*)) {
  v1::Scene scene = tiny_scene();
  v1::Geometry* g = scene.add_geometry();
  g->set_material("grey");
  fill(g);
  return scene;
}

void expect_single_issue(const v1::Scene& scene, const std::string& field,
                         const std::string& message) {
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  EXPECT_FALSE(conversion.ok());
  ASSERT_EQ(conversion.issues.size(), 1u) << describe_issues(conversion.issues);
  EXPECT_EQ(conversion.issues[0].field, field) << describe_issues(conversion.issues);
  EXPECT_NE(conversion.issues[0].message.find(message), std::string::npos)
      << "message was: " << conversion.issues[0].message;
}

TEST(ShapesFromProto, ConvertsEveryNewShapeAndTheTransform) {
  v1::Scene scene = tiny_scene();
  const auto add = [&]() {
    v1::Geometry* g = scene.add_geometry();
    g->set_material("grey");
    return g;
  };
  set_vec3(add()->mutable_plane()->mutable_normal(), 0, 1, 0);  // geometry[2]
  {
    v1::Disk* d = add()->mutable_disk();
    set_vec3(d->mutable_normal(), 0, 0, 1);
    d->set_radius(2);
    d->set_inner_radius(0.5);
  }
  {
    v1::Geometry* g = add();
    v1::Cylinder* c = g->mutable_cylinder();
    set_vec3(c->mutable_axis(), 1, 0, 0);
    c->set_radius(0.5);
    c->set_height(2);
    c->set_caps(true);
    v1::Transform* t = g->mutable_transform();
    set_vec3(t->mutable_translate(), 1, 2, 3);
    set_vec3(t->mutable_rotate()->mutable_axis(), 0, 1, 0);
    t->mutable_rotate()->set_degrees(30);
    set_vec3(t->mutable_scale(), 2, 2, 2);
  }
  {
    v1::Cone* c = add()->mutable_cone();
    set_vec3(c->mutable_axis(), 0, 1, 0);
    c->set_base_radius(1);
    c->set_height(2);
  }
  {
    v1::Torus* t = add()->mutable_torus();
    set_vec3(t->mutable_axis(), 0, 1, 0);
    t->set_major_radius(1);
    t->set_minor_radius(1.5);  // spindle: accepted
  }
  {
    v1::SdfBox* b = add()->mutable_sdf_box();
    set_vec3(b->mutable_half_extent(), 1, 2, 3);
    b->set_rounding(0.5);
  }
  {
    v1::SdfTorus* t = add()->mutable_sdf_torus();
    set_vec3(t->mutable_axis(), 0, 0, 1);
    t->set_major_radius(1);
    t->set_minor_radius(0.25);
  }
  {
    v1::Geometry* g = add();
    v1::SdfCapsule* c = g->mutable_sdf_capsule();
    set_vec3(c->mutable_b(), 0, 1, 0);
    c->set_radius(0.5);
    set_vec3(g->mutable_transform()->mutable_translate(), 0, 0, -1);  // rotate, scale unset
  }
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_TRUE(conversion.ok()) << describe_issues(conversion.issues);
  const SceneDescription& d = *conversion.scene;
  ASSERT_EQ(d.planes.size(), 1u);
  EXPECT_EQ(d.planes[0].source_index, 2u);
  ASSERT_EQ(d.disks.size(), 1u);
  EXPECT_DOUBLE_EQ(d.disks[0].inner_radius, 0.5);
  ASSERT_EQ(d.cylinders.size(), 1u);
  EXPECT_TRUE(d.cylinders[0].caps);
  ASSERT_TRUE(d.cylinders[0].transform.has_value());
  EXPECT_EQ(d.cylinders[0].transform->translate, glm::dvec3(1, 2, 3));
  EXPECT_EQ(d.cylinders[0].transform->rotate_axis, glm::dvec3(0, 1, 0));
  EXPECT_DOUBLE_EQ(d.cylinders[0].transform->rotate_degrees, 30.0);
  EXPECT_EQ(d.cylinders[0].transform->scale, glm::dvec3(2.0));
  ASSERT_EQ(d.cones.size(), 1u);
  EXPECT_DOUBLE_EQ(d.cones[0].top_radius, 0.0);
  EXPECT_FALSE(d.cones[0].transform.has_value());
  ASSERT_EQ(d.tori.size(), 1u);
  ASSERT_EQ(d.sdf_boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(d.sdf_boxes[0].rounding, 0.5);
  ASSERT_EQ(d.sdf_tori.size(), 1u);
  ASSERT_EQ(d.sdf_capsules.size(), 1u);
  EXPECT_EQ(d.sdf_capsules[0].source_index, 9u);
  ASSERT_TRUE(d.sdf_capsules[0].transform.has_value());
  EXPECT_EQ(d.sdf_capsules[0].transform->scale, glm::dvec3(1.0));  // unset: identity
  EXPECT_DOUBLE_EQ(d.sdf_capsules[0].transform->rotate_degrees, 0.0);
}

TEST(ShapesFromProto, RangeErrorsUseTheShapesProtobufPath) {
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_cylinder()->mutable_axis(), 0, 1, 0);
                        g->mutable_cylinder()->set_radius(-1);
                        g->mutable_cylinder()->set_height(1);
                      }),
                      "geometry[2].cylinder.radius", "must be > 0, got -1");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        g->mutable_cylinder()->mutable_axis();  // set to (0, 0, 0)
                        g->mutable_cylinder()->set_radius(1);
                        g->mutable_cylinder()->set_height(1);
                      }),
                      "geometry[2].cylinder.axis", "zero vector");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_disk()->mutable_normal(), 0, 1, 0);
                        g->mutable_disk()->set_radius(1);
                        g->mutable_disk()->set_inner_radius(2);
                      }),
                      "geometry[2].disk.inner_radius", "[0, radius)");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_cone()->mutable_axis(), 0, 1, 0);
                        g->mutable_cone()->set_height(1);
                      }),
                      "geometry[2].cone.base_radius", "both be 0");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_sdf_torus()->mutable_axis(), 0, 1, 0);
                        g->mutable_sdf_torus()->set_major_radius(1);
                        g->mutable_sdf_torus()->set_minor_radius(1);
                      }),
                      "geometry[2].sdf_torus.minor_radius", "< major_radius");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_sdf_box()->mutable_half_extent(), 1, 1, 1);
                        g->mutable_sdf_box()->set_rounding(-0.1);
                      }),
                      "geometry[2].sdf_box.rounding", "must be >= 0, got -0.1");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        set_vec3(g->mutable_sdf_box()->mutable_half_extent(), 1, 0.5, 1);
                        g->mutable_sdf_box()->set_rounding(0.6);
                      }),
                      "geometry[2].sdf_box.rounding", "smallest half extent");
  expect_single_issue(with_shape([](v1::Geometry* g) { g->mutable_sdf_capsule(); }),
                      "geometry[2].sdf_capsule.radius", "must be > 0, got 0");
  expect_single_issue(
      with_shape([](v1::Geometry* g) {
        set_vec3(g->mutable_torus()->mutable_axis(), 0, 1, 0);
        g->mutable_torus()->set_major_radius(1);
        g->mutable_torus()->set_minor_radius(std::numeric_limits<double>::infinity());
      }),
      "geometry[2].torus.minor_radius", "finite");
  expect_single_issue(with_shape([](v1::Geometry* g) { g->mutable_plane(); }),
                      "geometry[2].plane.normal", "zero vector");
}

TEST(ShapesFromProto, EmittingPlanesAreRejected) {
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        g->set_material("lamp");
                        set_vec3(g->mutable_plane()->mutable_normal(), 0, 1, 0);
                      }),
                      "geometry[2].material", "cannot emit");
}

// Hidden shapes are hidden from camera rays only: every other ray hits them, so an emitter
// without a light sampler (a torus) may be hidden too.
TEST(ShapesFromProto, HiddenEmittersOfEveryTypeAreAccepted) {
  const v1::Scene scene = with_shape([](v1::Geometry* g) {
    g->set_material("lamp");
    g->set_visible(false);
    g->mutable_torus()->set_major_radius(1);
    g->mutable_torus()->set_minor_radius(0.25);
    set_vec3(g->mutable_torus()->mutable_axis(), 0, 1, 0);
  });
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_TRUE(conversion.ok()) << describe_issues(conversion.issues);
  ASSERT_EQ(conversion.scene->tori.size(), 1u);
  EXPECT_FALSE(conversion.scene->tori[0].visible);
}

TEST(ShapesFromProto, TransformErrorsNameTheTransformField) {
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        g->mutable_sphere()->set_radius(1);
                        set_vec3(g->mutable_transform()->mutable_scale(), 1, 0, 1);
                      }),
                      "geometry[2].transform.scale", "singular");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        g->mutable_sphere()->set_radius(1);
                        g->mutable_transform()->mutable_rotate()->set_degrees(45);
                      }),
                      "geometry[2].transform.rotate.axis", "zero vector");
  expect_single_issue(with_shape([](v1::Geometry* g) {
                        g->mutable_sphere()->set_radius(1);
                        set_vec3(g->mutable_transform()->mutable_translate(), 0,
                                 std::numeric_limits<double>::quiet_NaN(), 0);
                      }),
                      "geometry[2].transform.translate.y", "finite");
}

TEST(ShapesFromProto, MeshNormalsAndUvsArePerVertex) {
  const auto mesh_scene = [](int normals, int uvs, double bad) {
    v1::Scene scene = tiny_scene();
    v1::Geometry* g = scene.add_geometry();
    g->set_material("grey");
    v1::TriangleMesh* mesh = g->mutable_mesh();
    for (double p : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0}) mesh->add_positions(p);
    for (unsigned i : {0u, 1u, 2u}) mesh->add_indices(i);
    for (int i = 0; i < normals; ++i) mesh->add_normals(i % 3 == 2 ? 1.0 : bad);
    for (int i = 0; i < uvs; ++i) mesh->add_uvs(0.5);
    return scene;
  };
  {
    const SceneConversion conversion = scene_from_proto(mesh_scene(9, 6, 0.0), tiny_settings());
    ASSERT_TRUE(conversion.ok()) << describe_issues(conversion.issues);
    const TriangleMeshDesc& mesh = conversion.scene->meshes.at(0);
    ASSERT_EQ(mesh.normals.size(), 3u);
    EXPECT_EQ(mesh.normals[1], glm::dvec3(0, 0, 1));
    ASSERT_EQ(mesh.uvs.size(), 3u);
    EXPECT_EQ(mesh.uvs[2], glm::dvec2(0.5, 0.5));
  }
  expect_single_issue(mesh_scene(6, 0, 0.0), "geometry[2].mesh.normals",
                      "must be empty or x, y, z per vertex (9 numbers), got 6");
  expect_single_issue(mesh_scene(0, 4, 0.0), "geometry[2].mesh.uvs",
                      "must be empty or u, v per vertex (6 numbers), got 4");
  expect_single_issue(mesh_scene(9, 0, std::numeric_limits<double>::infinity()),
                      "geometry[2].mesh.normals[0]", "finite");
}

}  // namespace
}  // namespace tessera::server
