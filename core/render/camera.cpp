#include "tessera/render/camera.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace tessera {

namespace {

// The camera's orthonormal frame and the image's half extents: on the plane at distance 1
// for a perspective camera, in world units for an orthographic one.
struct CameraFrame {
  glm::dvec3 forward, right, up;
  double half_width = 0.0, half_height = 0.0;
  double focus_distance = 1.0;
  bool orthographic = false;
};

CameraFrame frame_of(const CameraDesc& desc, std::uint32_t width, std::uint32_t height) {
  CameraFrame f;
  const glm::dvec3 view = desc.look_at - desc.position;
  f.forward = glm::normalize(view);
  f.right = glm::normalize(glm::cross(f.forward, desc.up));
  f.up = glm::cross(f.right, f.forward);
  f.orthographic = desc.projection == "orthographic";
  const double tan_half = std::tan(glm::radians(desc.fov_degrees) * 0.5);
  const double look_distance = glm::length(view);
  f.half_height = tan_half;
  if (f.orthographic)
    f.half_height = desc.ortho_height > 0.0 ? 0.5 * desc.ortho_height : tan_half * look_distance;
  f.half_width = f.half_height * static_cast<double>(width) / static_cast<double>(height);
  f.focus_distance = desc.focus_distance > 0.0 ? desc.focus_distance : look_distance;
  return f;
}

PixelFilterKind filter_kind(const std::string& name) {
  if (name == "gaussian") return PixelFilterKind::kGaussian;
  if (name == "blackman_harris") return PixelFilterKind::kBlackmanHarris;
  return PixelFilterKind::kBox;
}

}  // namespace

Camera Camera::from_description(const CameraDesc& desc, std::uint32_t width, std::uint32_t height) {
  const CameraFrame f = frame_of(desc, width, height);
  // Perspective: the image plane at distance 1; orthographic: through the camera position.
  const glm::dvec3 centre = f.orthographic ? desc.position : desc.position + f.forward;
  const glm::dvec3 top_left = centre - f.half_width * f.right + f.half_height * f.up;
  Camera camera;
  camera.origin = vec3(desc.position);
  // Perspective rays need the corner relative to the eye: as a world position, the
  // subtraction in generate() cancelled it to the ulp of the camera's coordinates, and a
  // camera 5,200 units out aimed every ray ~5e-4 rad off (6% of a pixel here).
  camera.top_left = f.orthographic ? vec3(top_left) : vec3(top_left - desc.position);
  camera.pixel_dx = vec3(f.right * (2.0 * f.half_width / width));
  camera.pixel_dy = vec3(-f.up * (2.0 * f.half_height / height));
  camera.forward = vec3(f.forward);
  camera.right = vec3(f.right);
  camera.up = vec3(f.up);
  camera.projection = f.orthographic ? Projection::kOrthographic : Projection::kPerspective;
  camera.lens_radius = f.orthographic ? 0.0f : static_cast<float>(desc.aperture_radius);
  camera.focus_distance = static_cast<float>(f.focus_distance);
  return camera;
}

Camera Camera::from_description(const CameraDesc& desc, const RenderSettings& render) {
  Camera camera = from_description(desc, render.width, render.height);
  camera.filter = PixelFilter::make(filter_kind(render.pixel_filter), render.filter_width);
  return camera;
}

CameraMatrices camera_matrices(const CameraDesc& desc, std::uint32_t width, std::uint32_t height) {
  const CameraFrame f = frame_of(desc, width, height);
  CameraMatrices m;
  // Rows right, up, -forward: the camera's frame with -Z along the view.
  m.world_to_camera = glm::lookAt(desc.position, desc.position + f.forward, f.up);
  constexpr double kNear = 0.01;
  glm::dmat4 projection(0.0);
  if (f.orthographic) {
    projection = glm::ortho(-f.half_width, f.half_width, -f.half_height, f.half_height, kNear, 1e6);
  } else {
    // OpenGL's perspective with the far plane at infinity: x / (-z tan), y / (-z tan).
    projection[0][0] = 1.0 / f.half_width;
    projection[1][1] = 1.0 / f.half_height;
    projection[2][2] = -1.0;
    projection[2][3] = -1.0;
    projection[3][2] = -2.0 * kNear;
  }
  m.world_to_screen = projection * m.world_to_camera;
  // Screen [-1, 1] with +Y up to NDC [0, 1] from the top-left: x' = (x + w) / 2,
  // y' = (w - y) / 2 before the divide.
  glm::dmat4 screen_to_ndc(1.0);
  screen_to_ndc[0][0] = 0.5;
  screen_to_ndc[1][1] = -0.5;
  screen_to_ndc[3][0] = 0.5;
  screen_to_ndc[3][1] = 0.5;
  m.world_to_ndc = screen_to_ndc * m.world_to_screen;
  return m;
}

}  // namespace tessera
