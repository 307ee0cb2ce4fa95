#pragma once
// What the per-pixel render tests share: a small scene for first-hit integrators and the
// exact camera ray they shoot, so a test can compare each pixel with an independent answer
// for that same ray.
#include <cstdint>

#include "tessera/math/rng.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera::test {

// One white lambertian material (index 0), one sample per pixel, tiles of 16.
inline SceneDescription first_hit_scene(const CameraDesc& camera, std::uint32_t width,
                                        std::uint32_t height, IntegratorKind integrator,
                                        std::uint64_t seed) {
  SceneDescription scene;
  scene.camera = camera;
  MaterialDesc white;
  white.name = "white";
  scene.materials.push_back(white);
  scene.render.width = width;
  scene.render.height = height;
  scene.render.samples_per_pixel = 1;
  scene.render.tile_size = 16;
  scene.render.integrator = integrator;
  scene.render.seed = seed;
  return scene;
}

// The camera ray the first-hit integrators shoot for pixel (x, y) with one sample.
inline Ray first_sample_camera_ray(const SceneDescription& scene, std::uint32_t x,
                                   std::uint32_t y) {
  const Camera camera =
      Camera::from_description(scene.camera, scene.render.width, scene.render.height);
  SampleStream samples(scene.render.seed, x, y, 0, scene.render.sampler);
  float jx, jy;
  samples.next_2d(jx, jy);
  return camera.generate(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
}

}  // namespace tessera::test
