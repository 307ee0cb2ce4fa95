// Lights and the environment through protobuf: every field survives YAML -> description ->
// protobuf -> description, and protobuf errors name the field in the request's terms.
#include <gtest/gtest.h>

#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

TEST(LightsProto, LightsAndEnvironmentRoundTrip) {
  const LoadedScene loaded = load_scene_yaml(R"(
environment: { type: gradient, intensity: 0.4 }
lights:
  - { type: point, position: [1, 2, 3], color: [1, 0.5, 0.25], intensity: 40 }
  - { type: spot, position: [0, 4, 0], direction: [0, -1, 0.2], intensity: 100,
      cone_angle_degrees: 35, cone_falloff_degrees: 8 }
  - { type: sun, direction: [-1, -2, -1], irradiance: 3, angular_radius_degrees: 0.27 }
)",
                                             "lights.yaml", ".");
  const v1::Scene proto = scene_to_proto(loaded.scene);
  ASSERT_EQ(proto.lights_size(), 3);
  EXPECT_EQ(proto.lights(1).type(), "spot");
  EXPECT_DOUBLE_EQ(proto.lights(1).cone_angle_degrees(), 35.0);
  EXPECT_EQ(proto.environment().type(), "gradient");
  SceneConversion back = scene_from_proto(proto, settings_to_proto(loaded.scene.render));
  ASSERT_TRUE(back.ok()) << describe_issues(back.issues);
  EXPECT_EQ(back.scene->lights, loaded.scene.lights);
  EXPECT_EQ(back.scene->environment, loaded.scene.environment);

  // No environment in the description: none in the request, and none back.
  SceneDescription plain;
  const v1::Scene plain_proto = scene_to_proto(plain);
  EXPECT_FALSE(plain_proto.has_environment());
  SceneConversion plain_back = scene_from_proto(plain_proto, settings_to_proto(plain.render));
  ASSERT_TRUE(plain_back.ok()) << describe_issues(plain_back.issues);
  EXPECT_FALSE(plain_back.scene->environment.has_value());
}

TEST(LightsProto, ErrorsNameTheFieldInProtobufTerms) {
  v1::Scene scene;
  v1::Light* unset = scene.add_lights();  // type left empty
  unset->mutable_position()->set_y(1.0);
  v1::Light* spot = scene.add_lights();
  spot->set_type("spot");
  spot->set_cone_angle_degrees(200.0);
  scene.mutable_environment()->set_type("hdri");
  const SceneConversion conversion = scene_from_proto(scene, v1::RenderSettings{});
  ASSERT_FALSE(conversion.ok());
  std::vector<std::string> fields;
  for (const SceneIssue& issue : conversion.issues) fields.push_back(issue.field);
  EXPECT_NE(std::find(fields.begin(), fields.end(), "lights[0].type"), fields.end())
      << describe_issues(conversion.issues);
  EXPECT_NE(std::find(fields.begin(), fields.end(), "lights[1].cone_angle_degrees"), fields.end())
      << describe_issues(conversion.issues);
  EXPECT_NE(std::find(fields.begin(), fields.end(), "environment.type"), fields.end())
      << describe_issues(conversion.issues);
}

}  // namespace
}  // namespace tessera
