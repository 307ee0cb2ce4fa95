// The magnitude bound through the protobuf path: the same rule as YAML (the scene model's),
// with the field named in the request's terms.
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::tiny_scene;
using testing::tiny_settings;

std::string issues_of(const v1::Scene& scene) {
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  EXPECT_FALSE(conversion.ok());
  return describe_issues(conversion.issues);
}

TEST(MagnitudeFromProto, AbsurdFiniteValuesAreRefusedWithTheFieldNamed) {
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_camera()->mutable_position()->set_z(1e308);
    EXPECT_EQ(issues_of(scene).rfind("camera.position: must be within +-1e+12", 0), 0u)
        << issues_of(scene);
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_materials(1)->mutable_emission()->set_x(1e308);
    EXPECT_EQ(issues_of(scene).rfind("materials[1].emission: must be within", 0), 0u)
        << issues_of(scene);
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_geometry(0)->mutable_sphere()->set_radius(1e300);
    EXPECT_EQ(issues_of(scene).rfind("geometry[0].sphere.radius: must be within", 0), 0u)
        << issues_of(scene);
  }
  {
    v1::Scene scene = tiny_scene();
    v1::TriangleMesh& mesh = *scene.add_geometry()->mutable_mesh();
    scene.mutable_geometry(2)->set_material("grey");
    for (const double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1e20, 0.0}) mesh.add_positions(v);
    for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 1u}) mesh.add_indices(i);
    EXPECT_EQ(issues_of(scene).rfind("geometry[2].mesh.positions[2]: must be within", 0), 0u)
        << issues_of(scene);
  }
}

}  // namespace
}  // namespace tessera::server
