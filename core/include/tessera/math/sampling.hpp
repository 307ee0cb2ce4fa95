#pragma once
#include <cmath>

#include "tessera/math/fast_trig.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

// `x` clamped into [0, 1) as a float, NaN to 0: a uniform number stretched back to [0, 1) from
// a part of it (a light pick's remainder), whose rounding can reach 1 or fall below 0.
TESSERA_HD TESSERA_INLINE float clamp_below_one(float x) {
  return glm::min(glm::max(0.0f, x), 0x1.fffffep-1f);
}

// Cosine-weighted direction about +z; pdf = cos(theta) / pi.
TESSERA_HD TESSERA_INLINE vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = std::sqrt(u1);
  float sin_phi, cos_phi;
  fast_sincos_turns(u2, sin_phi, cos_phi);
  const float z = std::sqrt(glm::max(0.0f, 1.0f - u1));
  return vec3(r * cos_phi, r * sin_phi, z);
}

// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
TESSERA_HD TESSERA_INLINE vec3 sample_uniform_sphere(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(glm::max(0.0f, 1.0f - z * z));
  float sin_phi, cos_phi;
  fast_sincos_turns(u2, sin_phi, cos_phi);
  return vec3(r * cos_phi, r * sin_phi, z);
}

// Uniform barycentrics on a triangle (Heitz 2019 low-distortion map is overkill here).
TESSERA_HD TESSERA_INLINE vec2 sample_uniform_triangle(float u1, float u2) {
  const float su = std::sqrt(u1);
  return vec2(1.0f - su, u2 * su);
}

}  // namespace tessera
