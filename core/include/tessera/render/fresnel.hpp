#pragma once
// Exact unpolarised Fresnel reflectance: at a dielectric interface (real relative index) and
// at a conductor (complex index eta + i k per RGB channel, seen from a medium of index 1).
// Both are the mean of the s- and p-polarised reflectances.
#include <cmath>

#include "tessera/math/vec.hpp"

namespace tessera {

// Reflectance of a dielectric interface for light arriving at |cos_i| (cos_i measured from
// the normal on the arriving side), `eta` = n_transmitted / n_incident. 1 on total internal
// reflection.
TESSERA_HD TESSERA_INLINE float fresnel_dielectric(float cos_i, float eta) {
  cos_i = glm::clamp(std::fabs(cos_i), 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(glm::max(0.0f, 1.0f - sin2_t));
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// Reflectance of a conductor with complex index eta + i k for light arriving from a medium
// of index 1 at cos_i. Closed form of |r_s|^2 and |r_p|^2 with a^2 + b^2 = |(eta + i k)^2 -
// sin^2|, written with real arithmetic so it runs on the device (Born & Wolf, section 14.2;
// the same expressions as pbrt-v3's FrConductor). k = 0 gives the dielectric reflectance.
TESSERA_HD TESSERA_INLINE float fresnel_conductor(float cos_i, float eta, float k) {
  cos_i = glm::clamp(std::fabs(cos_i), 0.0f, 1.0f);
  const float cos2 = cos_i * cos_i;
  const float sin2 = 1.0f - cos2;
  const float eta2 = eta * eta;
  const float k2 = k * k;
  const float t0 = eta2 - k2 - sin2;
  const float a2_plus_b2 = std::sqrt(glm::max(0.0f, t0 * t0 + 4.0f * eta2 * k2));
  const float a = std::sqrt(glm::max(0.0f, 0.5f * (a2_plus_b2 + t0)));
  const float t1 = a2_plus_b2 + cos2;
  const float t2 = 2.0f * cos_i * a;
  const float rs = (t1 - t2) / glm::max(t1 + t2, 1e-20f);
  const float t3 = cos2 * a2_plus_b2 + sin2 * sin2;
  const float t4 = t2 * sin2;
  const float rp = rs * (t3 - t4) / glm::max(t3 + t4, 1e-20f);
  return glm::clamp(0.5f * (rp + rs), 0.0f, 1.0f);
}

TESSERA_HD TESSERA_INLINE vec3 fresnel_conductor(float cos_i, const vec3& eta, const vec3& k) {
  return vec3(fresnel_conductor(cos_i, eta.x, k.x), fresnel_conductor(cos_i, eta.y, k.y),
              fresnel_conductor(cos_i, eta.z, k.z));
}

}  // namespace tessera
