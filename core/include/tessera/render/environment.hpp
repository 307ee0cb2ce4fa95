#pragma once
// The environment: the radiance a ray that escapes the scene sees, by direction. A constant
// colour; RayON's sky, a vertical blend from white below to (0.5, 0.7, 1.0) above, times an
// intensity, exactly as RayON's miss program draws it (t = (y + 1) / 2 of the unit
// direction); or an equirectangular image, rotated about +y. The constant and the gradient
// are sampled uniformly over the sphere for next-event estimation (the gradient's
// luminance varies by less than 1.5x, so importance sampling it would gain little); the
// image by a 2D piecewise-constant distribution over its pixels weighted by luminance times
// sin(theta) (render/environment_map.hpp builds it).
#include <cmath>
#include <cstdint>

#include "tessera/math/piecewise_constant_2d.hpp"
#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

enum class EnvironmentKind : std::uint32_t { kConstant = 0, kGradient, kImage };

// RayON's sky colour straight up; straight down it is white.
inline constexpr float kGradientZenith[3] = {0.5f, 0.7f, 1.0f};

struct Environment {
  EnvironmentKind kind = EnvironmentKind::kConstant;
  vec3 scale{0.0f};  // constant: the radiance; gradient and image: colour times intensity
  // kImage: width x height linear RGB pixels (already times scale), rows from the zenith
  // (theta = 0) down; column u = (phi + pi) / 2 pi with phi = atan2(-z, x) in the image's
  // frame, which is the world turned by the rotation about +y.
  const float* image = nullptr;
  std::uint32_t width = 0, height = 0;
  PiecewiseConstant2D distribution;
  float cos_rotation = 1.0f, sin_rotation = 0.0f;
  vec3 image_average{0.0f};  // the image's radiance averaged over the sphere

  // Radiance arriving along -unit_direction (seen looking along unit_direction).
  TESSERA_HD vec3 radiance(const vec3& unit_direction) const {
    if (kind == EnvironmentKind::kImage) {
      float sin_theta;
      const vec2 uv = to_uv(unit_direction, sin_theta);
      const std::size_t pixel =
          static_cast<std::size_t>(PiecewiseConstant2D::cell(uv.y, height)) * width +
          PiecewiseConstant2D::cell(uv.x, width);
      return vec3(image[3 * pixel], image[3 * pixel + 1], image[3 * pixel + 2]);
    }
    if (kind == EnvironmentKind::kGradient) {
      const float t = 0.5f * (unit_direction.y + 1.0f);
      const vec3 zenith(kGradientZenith[0], kGradientZenith[1], kGradientZenith[2]);
      return ((1.0f - t) * vec3(1.0f) + t * zenith) * scale;
    }
    return scale;
  }

  // The average radiance over the sphere. The gradient's t is uniform in [0, 1] over it
  // (z = cos(theta) is uniform on the sphere), so its average is the midpoint colour.
  vec3 average_radiance() const {
    if (kind == EnvironmentKind::kImage) return image_average;
    if (kind == EnvironmentKind::kGradient)
      return 0.5f *
             (vec3(1.0f) + vec3(kGradientZenith[0], kGradientZenith[1], kGradientZenith[2])) *
             scale;
    return scale;
  }

  bool black() const { return !(scale.x > 0.0f || scale.y > 0.0f || scale.z > 0.0f); }

  // A direction towards the environment, its solid-angle pdf (0: draw nothing) and the
  // radiance along it. An image's radiance is the sampled pixel's: looked up again from the
  // direction, a sample on a pixel's edge could round into its neighbour and carry that
  // pixel's radiance with this one's pdf (next to a bright pixel, a 1% bias).
  TESSERA_HD vec3 sample(float u1, float u2, float& pdf, vec3& seen) const {
    if (kind != EnvironmentKind::kImage) {
      pdf = 0.25f * kInvPi;
      const vec3 direction = sample_uniform_sphere(u1, u2);
      seen = radiance(direction);
      return direction;
    }
    float uv_pdf, sin_theta;
    std::uint32_t pixel;
    const vec3 direction = from_uv(distribution.sample(u1, u2, uv_pdf, pixel), sin_theta);
    pdf = sin_theta > 0.0f ? uv_pdf / (2.0f * kPi * kPi * sin_theta) : 0.0f;
    seen = vec3(image[3 * pixel], image[3 * pixel + 1], image[3 * pixel + 2]);
    return direction;
  }

  TESSERA_HD float pdf(const vec3& unit_direction) const {
    if (kind != EnvironmentKind::kImage) return 0.25f * kInvPi;
    float sin_theta;
    const vec2 uv = to_uv(unit_direction, sin_theta);
    return sin_theta > 0.0f ? distribution.pdf(uv) / (2.0f * kPi * kPi * sin_theta) : 0.0f;
  }

  // The image coordinates of a world direction (u along columns, v = theta / pi down rows).
  TESSERA_HD vec2 to_uv(const vec3& world, float& sin_theta) const {
    const vec3 d(cos_rotation * world.x - sin_rotation * world.z, world.y,
                 sin_rotation * world.x + cos_rotation * world.z);
    const float cos_theta = glm::clamp(d.y, -1.0f, 1.0f);
    sin_theta = std::sqrt(glm::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = std::atan2(-d.z, d.x);
    return vec2(glm::clamp((phi + kPi) * (0.5f * kInvPi), 0.0f, 1.0f),
                glm::clamp(std::acos(cos_theta) * kInvPi, 0.0f, 1.0f));
  }

  TESSERA_HD vec3 from_uv(const vec2& uv, float& sin_theta) const {
    const float phi = 2.0f * kPi * uv.x - kPi, theta = kPi * uv.y;
    sin_theta = std::sin(theta);
    const vec3 d(sin_theta * std::cos(phi), std::cos(theta), -sin_theta * std::sin(phi));
    return vec3(cos_rotation * d.x + sin_rotation * d.z, d.y,
                -sin_rotation * d.x + cos_rotation * d.z);
  }
};

}  // namespace tessera
