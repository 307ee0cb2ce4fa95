// `visible: false` hides a shape from camera rays only, as RayON means it: reflections,
// bounces and shadow rays still meet it, so a hidden light shows in a mirror and is weighed
// by MIS like any emitter, and a hidden occluder still casts its shadow. (Leaving hidden
// shapes out of every ray made a near-mirror lit by a hidden light a source of fireflies:
// only light sampling could find the light, and a sharp lobe needs BSDF sampling.)
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "scene_materials.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

using glm::dvec3;

// A floor, a back wall, a mirror, a rough metal and a diffuse sphere, lit by a rectangle
// light above the top of the view. Out of the camera's sight: the light, a small diffuse
// ball under it (it shades the floor) and a wall behind the camera (it reflects light back
// into the room). `hide` hides those three.
SceneDescription room(bool hide) {
  SceneDescription scene;
  scene.camera.position = {0.0, 1.0, 4.0};
  scene.camera.look_at = {0.0, 0.8, 0.0};
  scene.camera.fov_degrees = 40.0;
  MaterialDesc mirror;
  mirror.name = "mirror";
  mirror.type = MaterialType::kMetal;
  mirror.albedo = dvec3(0.9);
  MaterialDesc rough = mirror;
  rough.name = "rough";
  rough.roughness = 0.05;
  scene.materials = {test::lambertian_material("white", dvec3(0.7)),
                     test::light_material("lamp", dvec3(12.0)), mirror, rough};
  scene.quads.push_back(
      QuadDesc{.corner = {-3, 0, -2}, .u = {6, 0, 0}, .v = {0, 0, 8}, .material = 0});
  scene.quads.push_back(
      QuadDesc{.corner = {-3, 0, -2}, .u = {6, 0, 0}, .v = {0, 4, 0}, .material = 0});
  scene.quads.push_back(QuadDesc{.corner = {-0.5, 3.0, -0.5},
                                 .u = {1, 0, 0},
                                 .v = {0, 0, 1},
                                 .material = 1,
                                 .visible = !hide});
  scene.spheres.push_back(SphereDesc{.center = {-0.9, 0.5, 0.0}, .radius = 0.5, .material = 2});
  scene.spheres.push_back(SphereDesc{.center = {0.4, 0.4, 0.3}, .radius = 0.4, .material = 3});
  scene.spheres.push_back(SphereDesc{.center = {1.3, 0.3, -0.4}, .radius = 0.3, .material = 0});
  scene.spheres.push_back(
      SphereDesc{.center = {0.0, 2.4, 0.5}, .radius = 0.15, .material = 0, .visible = !hide});
  scene.planes.push_back(
      PlaneDesc{.point = {0, 0, 6}, .normal = {0, 0, -1}, .material = 0, .visible = !hide});
  scene.render.width = 32;
  scene.render.height = 32;
  scene.render.samples_per_pixel = 8;
  scene.render.max_depth = 6;
  scene.render.seed = 3;
  return scene;
}

// No camera ray meets the hidden shapes, and every other ray meets them as when they are
// visible: the two images are the same bit for bit.
TEST(HiddenShapes, EveryRayButTheCamerasMeetsThem) {
  const std::vector<float> visible = render_image(*PreparedScene::build(room(false)));
  const std::vector<float> hidden = render_image(*PreparedScene::build(room(true)));
  ASSERT_EQ(visible.size(), hidden.size());
  std::size_t different = 0;
  for (std::size_t i = 0; i < visible.size(); ++i) different += visible[i] != hidden[i];
  EXPECT_EQ(different, 0u);

  // And they matter: without the ball and the back wall the image changes.
  SceneDescription fewer = room(true);
  fewer.spheres.pop_back();
  fewer.planes.clear();
  const std::vector<float> without = render_image(*PreparedScene::build(fewer));
  std::size_t changed = 0;
  for (std::size_t i = 0; i < visible.size(); ++i) changed += without[i] != hidden[i];
  EXPECT_GT(changed, visible.size() / 2);
}

// A camera looking straight at a hidden emitter sees what lies beyond it (here nothing:
// the background), as if it were not there.
TEST(HiddenShapes, CameraRaysPassThroughAHiddenLight) {
  SceneDescription scene = room(false);
  scene.spheres.pop_back();  // the ball under the light
  scene.camera.position = {0.0, 1.0, 2.0};
  scene.camera.look_at = {0.0, 3.0, 0.0};  // the light fills the middle of the view
  const std::vector<float> seen = render_image(*PreparedScene::build(scene));
  scene.quads[2].visible = false;
  const std::vector<float> hidden = render_image(*PreparedScene::build(scene));
  scene.quads.pop_back();
  const std::vector<float> without = render_image(*PreparedScene::build(scene));
  const std::uint32_t w = scene.render.width, h = scene.render.height;
  const std::size_t centre = (std::size_t{h / 2} * w + w / 2) * 4;
  EXPECT_FLOAT_EQ(seen[centre], 12.0f);  // the light's radiance, every sample
  EXPECT_EQ(hidden[centre], without[centre]);
  EXPECT_NE(hidden[centre], seen[centre]);
}

}  // namespace
}  // namespace tessera
