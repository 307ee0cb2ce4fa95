#pragma once
// Tiny scenes shared by the server tests: a lit sphere seen by a camera, small enough that
// a whole job renders in milliseconds.
#include "convert/scene_proto.hpp"
#include "tessera/v1/render.pb.h"
#include "tessera/v1/scene.pb.h"

namespace tessera::server::testing {

inline void set_vec3(v1::Vec3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

// Camera, a grey lambertian material, a light material, a sphere and an emissive rectangle.
inline v1::Scene tiny_scene() {
  v1::Scene scene;
  v1::Camera* camera = scene.mutable_camera();
  set_vec3(camera->mutable_position(), 0, 0, 5);
  set_vec3(camera->mutable_look_at(), 0, 0, 0);
  camera->set_fov_degrees(40);
  set_vec3(scene.mutable_background()->mutable_color(), 0.1, 0.1, 0.1);

  v1::Material* grey = scene.add_materials();
  grey->set_name("grey");
  grey->set_type(v1::MATERIAL_TYPE_LAMBERTIAN);
  v1::Material* light = scene.add_materials();
  light->set_name("lamp");
  light->set_type(v1::MATERIAL_TYPE_LIGHT);
  set_vec3(light->mutable_emission(), 4, 4, 4);

  v1::Geometry* ball = scene.add_geometry();
  ball->set_material("grey");
  set_vec3(ball->mutable_sphere()->mutable_center(), 0, 0, 0);
  ball->mutable_sphere()->set_radius(1);
  v1::Geometry* panel = scene.add_geometry();
  panel->set_material("lamp");
  set_vec3(panel->mutable_rectangle()->mutable_corner(), -1, 2, -1);
  set_vec3(panel->mutable_rectangle()->mutable_u(), 2, 0, 0);
  set_vec3(panel->mutable_rectangle()->mutable_v(), 0, 0, 2);
  return scene;
}

inline v1::RenderSettings tiny_settings(std::uint32_t width = 16, std::uint32_t height = 16,
                                        std::uint32_t tile_size = 8) {
  v1::RenderSettings settings;
  settings.set_width(width);
  settings.set_height(height);
  settings.set_samples_per_pixel(1);
  settings.set_max_depth(2);
  settings.set_tile_size(tile_size);
  return settings;
}

inline SceneDescription tiny_description(std::uint32_t width = 16, std::uint32_t height = 16,
                                         std::uint32_t tile_size = 8) {
  SceneConversion conversion =
      scene_from_proto(tiny_scene(), tiny_settings(width, height, tile_size));
  return std::move(*conversion.scene);
}

}  // namespace tessera::server::testing
