#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/render/pixel_filter.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

enum class Projection : std::uint8_t { kPerspective, kOrthographic };

// The sample dimension pair the thin lens draws its point on the aperture from. Far past
// any bounce's block (render/path_tracer.hpp: kCameraDimensions, kBounceDimensions), so a
// lens changes no other decision's numbers and a pinhole image stays what it was; the
// Sobol sampler scrambles every pair independently, so a distant pair is as good as any.
inline constexpr std::uint32_t kLensDimension = 0x7fff0000U;

// The camera. Pixel (0, 0) is the top-left corner of the image.
//   Perspective: rays from `origin` through the image plane at distance 1; with a lens
//   radius, a thin lens: rays from a point on the aperture disk through the point the
//   pinhole ray meets on the focus plane (at focus_distance along `forward`), so that
//   plane is sharp and points off it blur into discs (the circle of confusion).
//   Orthographic: parallel rays along `forward` from the image rectangle, which is
//   centred on the camera position.
struct Camera {
  vec3 origin;    // perspective: the eye (lens centre)
  vec3 top_left;  // perspective: the image plane's top-left corner at distance 1,
                  // relative to `origin`; orthographic: the image rectangle's top-left
                  // corner, world position
  vec3 pixel_dx;  // step of one pixel to the right
  vec3 pixel_dy;  // step of one pixel down
  vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  vec3 right{1.0f, 0.0f, 0.0f};     // unit, the lens's axes
  vec3 up{0.0f, 1.0f, 0.0f};
  float lens_radius = 0.0f;  // 0: pinhole
  float focus_distance = 1.0f;
  Projection projection = Projection::kPerspective;
  PixelFilter filter;

  // Built in double so that cameras far from the origin keep a precise frame.
  static Camera from_description(const CameraDesc& desc, std::uint32_t width, std::uint32_t height);
  // With the render settings' pixel filter.
  static Camera from_description(const CameraDesc& desc, const RenderSettings& render);

  // The ray cone of a pixel: its width at `distance` along a camera ray, world units, and
  // how fast that grows per unit distance (0 for orthographic views, whose rays are parallel).
  TESSERA_HD float pixel_spread() const {
    return projection == Projection::kOrthographic ? 0.0f : glm::length(pixel_dy);
  }
  TESSERA_HD float footprint_at(float distance) const {
    return projection == Projection::kOrthographic ? glm::length(pixel_dy)
                                                   : distance * glm::length(pixel_dy);
  }

  // (px, py) in pixel units: the pixel's integer corner plus a sample offset; the ray
  // through the lens centre.
  TESSERA_HD Ray generate(float px, float py) const {
    Ray ray;
    if (projection == Projection::kOrthographic) {
      ray.origin = top_left + px * pixel_dx + py * pixel_dy;
      ray.direction = forward;
    } else {
      ray.origin = origin;
      ray.direction = glm::normalize(top_left + px * pixel_dx + py * pixel_dy);
    }
    ray.t_min = 0.0f;
    ray.t_max = kInfinity;
    return ray;
  }

  // Through the thin lens at the point of the aperture disk that (lens_u1, lens_u2) pick.
  TESSERA_HD Ray generate(float px, float py, float lens_u1, float lens_u2) const {
    Ray ray = generate(px, py);
    if (!(lens_radius > 0.0f)) return ray;
    // Concentric mapping keeps the sampler's stratification on the disk.
    float dx = 2.0f * lens_u1 - 1.0f;
    float dy = 2.0f * lens_u2 - 1.0f;
    float r = 0.0f, phi = 0.0f;
    if (dx != 0.0f || dy != 0.0f) {
      constexpr float kQuarterPi = 0.78539816f;
      if (std::fabs(dx) > std::fabs(dy)) {
        r = dx;
        phi = kQuarterPi * (dy / dx);
      } else {
        r = dy;
        phi = 2.0f * kQuarterPi - kQuarterPi * (dx / dy);
      }
    }
    dx = lens_radius * r * std::cos(phi);
    dy = lens_radius * r * std::sin(phi);
    // The pinhole ray meets the focus plane at t = focus_distance / cos(angle to forward).
    // Both points relative to the eye, so that a camera far from the origin loses nothing
    // to the ulp of its own coordinates (see generate above).
    const vec3 focus = ray.direction * (focus_distance / glm::dot(ray.direction, forward));
    const vec3 lens_point = dx * right + dy * up;
    ray.origin = origin + lens_point;
    ray.direction = glm::normalize(focus - lens_point);
    return ray;
  }

  // The camera ray of one sample of pixel (x, y): its position in the pixel from the
  // stream's first pair (drawn from the pixel filter), its lens point from kLensDimension.
  TESSERA_HD Ray generate_sample(std::uint32_t x, std::uint32_t y, SampleStream& samples) const {
    float jx, jy;
    samples.next_2d_kept(jx, jy);
    const float px = static_cast<float>(x) + filter.position(jx);
    const float py = static_cast<float>(y) + filter.position(jy);
    if (!(lens_radius > 0.0f)) return generate(px, py);
    const std::uint32_t next = samples.dimension();
    float lu, lv;
    samples.set_dimension(kLensDimension);
    samples.next_2d(lu, lv);
    samples.set_dimension(next);
    return generate(px, py, lu, lv);
  }
};

// The camera matrices of the image header (OpenEXR's worldToCamera and worldToNDC, and
// worldToScreen as OpenImageIO and Arnold write it). Camera space looks down -Z with +Y
// up and +X right. Screen: x and y over [-1, 1] across the image, +Y up, after the divide
// by w; z is OpenGL's depth with the near plane at 0.01 (perspective: far at infinity;
// orthographic: far at 1e6). NDC (RenderMan's, OpenImageIO's "worldtoNDC"): x and y over
// [0, 1], (0, 0) the image's top-left corner, +Y down. Column vectors (glm).
struct CameraMatrices {
  glm::dmat4 world_to_camera;
  glm::dmat4 world_to_screen;
  glm::dmat4 world_to_ndc;
};
CameraMatrices camera_matrices(const CameraDesc& desc, std::uint32_t width, std::uint32_t height);

}  // namespace tessera
