#pragma once
#include <cmath>

#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

// Schlick's approximation of unpolarised Fresnel reflectance.
TESSERA_HD TESSERA_INLINE float schlick_reflectance(float cos_theta, float eta_ratio) {
  float r0 = (1.0f - eta_ratio) / (1.0f + eta_ratio);
  r0 *= r0;
  const float m = 1.0f - glm::clamp(cos_theta, 0.0f, 1.0f);
  return r0 + (1.0f - r0) * m * m * m * m * m;
}

TESSERA_HD TESSERA_INLINE vec3 reflect(const vec3& d, const vec3& n) {
  return d - 2.0f * glm::dot(d, n) * n;
}

// Refracts unit `d` through unit `n` (facing against d) with eta = n_incident / n_transmitted.
// Returns false on total internal reflection.
TESSERA_HD TESSERA_INLINE bool refract(const vec3& d, const vec3& n, float eta, vec3& out) {
  const float cos_i = glm::min(-glm::dot(d, n), 1.0f);
  const float sin2_t = eta * eta * glm::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return false;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  out = eta * d + (eta * cos_i - cos_t) * n;
  return true;
}

// Mirror direction perturbed by a roughness-scaled point in the unit ball (RayON's fuzzy
// metal). Returns a zero vector when the perturbation sends the ray below the surface.
TESSERA_HD TESSERA_INLINE vec3 fuzzy_reflect(const vec3& d, const vec3& n, float roughness,
                                             float u1, float u2, float u3) {
  vec3 r = reflect(d, n);
  if (roughness > 0.0f) {
    const vec3 ball = sample_uniform_sphere(u1, u2) * std::cbrt(u3);
    r = glm::normalize(r + roughness * ball);
  }
  return glm::dot(r, n) > 0.0f ? r : vec3(0.0f);
}

}  // namespace tessera
