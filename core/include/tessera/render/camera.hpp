#pragma once
#include <cstdint>

#include "tessera/geometry/ray.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Pinhole camera. Pixel (0, 0) is the top-left corner of the image.
struct Camera {
  vec3 origin;
  vec3 top_left;  // world position of the image plane's top-left corner at distance 1
  vec3 pixel_dx;  // step of one pixel to the right
  vec3 pixel_dy;  // step of one pixel down

  // Built in double so that cameras far from the origin keep a precise frame.
  static Camera from_description(const CameraDesc& desc, std::uint32_t width, std::uint32_t height);

  // (px, py) in pixel units: the pixel's integer corner plus a sample offset in [0, 1).
  TESSERA_HD Ray generate(float px, float py) const {
    Ray ray;
    ray.origin = origin;
    ray.direction = glm::normalize(top_left + px * pixel_dx + py * pixel_dy - origin);
    ray.t_min = 0.0f;
    ray.t_max = kInfinity;
    return ray;
  }
};

}  // namespace tessera
