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

  // An image environment travels with its pixels.
  SceneDescription imaged;
  imaged.environment = EnvironmentDesc{.type = "image",
                                       .rotation_degrees = 45.0,
                                       .image_width = 2,
                                       .image_height = 1,
                                       .image_pixels = {1, 2, 3, 4, 5, 6}};
  SceneConversion imaged_back =
      scene_from_proto(scene_to_proto(imaged), settings_to_proto(imaged.render));
  ASSERT_TRUE(imaged_back.ok()) << describe_issues(imaged_back.issues);
  EXPECT_EQ(imaged_back.scene->environment, imaged.environment);

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
  v1::Scene imaged;
  imaged.mutable_environment()->set_type("image");
  imaged.mutable_environment()->set_image_width(2);
  imaged.mutable_environment()->set_image_height(2);
  imaged.mutable_environment()->add_image_pixels(1.0f);
  const SceneConversion short_pixels = scene_from_proto(imaged, v1::RenderSettings{});
  ASSERT_FALSE(short_pixels.ok());
  EXPECT_EQ(short_pixels.issues[0].field, "environment.image_pixels")
      << describe_issues(short_pixels.issues);
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
