#include "tessera/render/camera.hpp"

#include <cmath>

namespace tessera {

Camera Camera::from_description(const CameraDesc& desc, std::uint32_t width, std::uint32_t height) {
  const glm::dvec3 forward = glm::normalize(desc.look_at - desc.position);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, desc.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const double half_height = std::tan(glm::radians(desc.fov_degrees) * 0.5);
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  const double half_width = half_height * aspect;
  const glm::dvec3 top_left = desc.position + forward - half_width * right + half_height * up;
  Camera camera;
  camera.origin = vec3(desc.position);
  camera.top_left = vec3(top_left);
  camera.pixel_dx = vec3(right * (2.0 * half_width / width));
  camera.pixel_dy = vec3(-up * (2.0 * half_height / height));
  return camera;
}

}  // namespace tessera
