// The camera, pixel filter, image, clamp and structure fields through YAML: values land in the
// description, and bad ones are errors naming the field and the reason.
#include <gtest/gtest.h>

#include <string>

#include "scene_error_of.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "scene.yaml", ".");
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

TEST(CameraFields, ReadFromYaml) {
  const SceneDescription s =
      load(
          "camera: { position: [0, 0, 5], look_at: [0, 0, 0], aperture_radius: 0.1,\n"
          "          focus_distance: 4 }\n"
          "render: { pixel_filter: blackman_harris, filter_width: 2.5, clamp: 10,\n"
          "          transparent_background: true }\n")
          .scene;
  EXPECT_EQ(s.camera.aperture_radius, 0.1);
  EXPECT_EQ(s.camera.focus_distance, 4.0);
  EXPECT_EQ(s.render.pixel_filter, "blackman_harris");
  EXPECT_EQ(s.render.filter_width, 2.5);
  EXPECT_EQ(s.render.clamp, 10.0);
  EXPECT_TRUE(s.render.transparent_background);
  const SceneDescription ortho =
      load("camera: { projection: orthographic, ortho_height: 3 }\n").scene;
  EXPECT_EQ(ortho.camera.projection, "orthographic");
  EXPECT_EQ(ortho.camera.ortho_height, 3.0);
}

TEST(CameraFields, BadValuesNameTheFieldAndTheReason) {
  const SceneIssue projection = load_error("camera: { projection: ortho }\n");
  EXPECT_EQ(projection.field, "camera.projection");
  EXPECT_NE(projection.message.find("orthographic"), std::string::npos) << projection.message;
  EXPECT_EQ(load_error("camera: { aperture_radius: -1 }\n").field, "camera.aperture_radius");
  EXPECT_EQ(load_error("camera: { focus_distance: -2 }\n").field, "camera.focus_distance");
  EXPECT_EQ(load_error("camera: { ortho_height: -2 }\n").field, "camera.ortho_height");
  const SceneIssue lens_on_ortho =
      load_error("camera: { projection: orthographic, aperture_radius: 0.1 }\n");
  EXPECT_EQ(lens_on_ortho.field, "camera.aperture_radius");
  EXPECT_NE(lens_on_ortho.message.find("orthographic"), std::string::npos);
  EXPECT_EQ(load_error("render: { pixel_filter: gauss }\n").field, "render.pixel_filter");
  EXPECT_EQ(load_error("render: { filter_width: 40 }\n").field, "render.filter_width");
  EXPECT_EQ(load_error("render: { clamp: -1 }\n").field, "render.clamp");
}

TEST(CameraFields, AccelBuilderIsOneOfItsChoices) {
  EXPECT_EQ(load("render: { accel_builder: spatial }\n").scene.render.accel_builder, "spatial");
  EXPECT_EQ(load("render: { accel_builder: binned }\n").scene.render.accel_builder, "binned");
  EXPECT_EQ(load("render: { spp: 4 }\n").scene.render.accel_builder, "");  // auto
  const SceneIssue bad = load_error("render: { accel_builder: sbvh }\n");
  EXPECT_EQ(bad.field, "render.accel_builder");
  EXPECT_NE(bad.message.find("binned"), std::string::npos) << bad.message;
}

}  // namespace
}  // namespace tessera
