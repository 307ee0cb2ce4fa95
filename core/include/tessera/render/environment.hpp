#pragma once
// The environment: the radiance a ray that escapes the scene sees, by direction. A constant
// colour, or RayON's sky: a vertical blend from white below to (0.5, 0.7, 1.0) above, times
// an intensity, exactly as RayON's miss program draws it (t = (y + 1) / 2 of the unit
// direction). Both are sampled uniformly over the sphere for next-event estimation: the
// gradient's luminance varies by less than 1.5x, so importance sampling it would gain little.
#include <cstdint>

#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

enum class EnvironmentKind : std::uint32_t { kConstant = 0, kGradient };

// RayON's sky colour straight up; straight down it is white.
inline constexpr float kGradientZenith[3] = {0.5f, 0.7f, 1.0f};

struct Environment {
  EnvironmentKind kind = EnvironmentKind::kConstant;
  vec3 scale{0.0f};  // constant: the radiance; gradient: the intensity, per channel

  // Radiance arriving along -unit_direction (seen looking along unit_direction).
  TESSERA_HD vec3 radiance(const vec3& unit_direction) const {
    if (kind == EnvironmentKind::kGradient) {
      const float t = 0.5f * (unit_direction.y + 1.0f);
      const vec3 zenith(kGradientZenith[0], kGradientZenith[1], kGradientZenith[2]);
      return ((1.0f - t) * vec3(1.0f) + t * zenith) * scale;
    }
    return scale;
  }

  // The average radiance over the sphere: the gradient's t is uniform in [0, 1] over it
  // (z = cos(theta) is uniform on the sphere), so its average is the midpoint colour.
  vec3 average_radiance() const {
    if (kind == EnvironmentKind::kGradient)
      return 0.5f *
             (vec3(1.0f) + vec3(kGradientZenith[0], kGradientZenith[1], kGradientZenith[2])) *
             scale;
    return scale;
  }

  bool black() const { return !(scale.x > 0.0f || scale.y > 0.0f || scale.z > 0.0f); }

  // A direction towards the environment and its solid-angle pdf.
  TESSERA_HD vec3 sample(float u1, float u2) const { return sample_uniform_sphere(u1, u2); }
  TESSERA_HD float pdf(const vec3&) const { return 0.25f * kInvPi; }
};

}  // namespace tessera
