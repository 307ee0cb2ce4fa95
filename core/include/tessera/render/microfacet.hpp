#pragma once
// The anisotropic Trowbridge-Reitz (GGX) microfacet distribution in the local shading frame
// (+z the macro normal, x the tangent along which the roughness is alpha_x): the normal
// distribution D, Smith's masking G1 and height-correlated masking-shadowing G2, and
// sampling of the visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible
// Normals", JCGT 7(4)). Conductors and rough dielectrics (bsdf.hpp) build on it.
#include <cmath>

#include "tessera/math/fast_trig.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

struct GgxDistribution {
  float alpha_x = 0.0f;
  float alpha_y = 0.0f;

  // Below this the lobe is narrower than float directions resolve: render it as a mirror.
  static constexpr float kSmoothAlpha = 1e-3f;

  TESSERA_HD bool effectively_smooth() const { return glm::max(alpha_x, alpha_y) < kSmoothAlpha; }

  // D(m) for a unit microfacet normal m: 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2), the
  // usual form with tan and cos multiplied out, which keeps its precision near the pole.
  TESSERA_HD float d(const vec3& m) const {
    if (m.z <= 0.0f) return 0.0f;
    const float x = m.x / alpha_x;
    const float y = m.y / alpha_y;
    const float s = x * x + y * y + m.z * m.z;
    return 1.0f / (kPi * alpha_x * alpha_y * s * s);
  }

  // Smith's Lambda(w) = (sqrt(1 + alpha(phi)^2 tan^2 theta) - 1) / 2.
  TESSERA_HD float lambda(const vec3& w) const {
    const float z2 = w.z * w.z;
    if (!(z2 > 0.0f)) return 1e30f;
    const float ax = alpha_x * w.x;
    const float ay = alpha_y * w.y;
    const float a2_tan2 = (ax * ax + ay * ay) / z2;
    return 0.5f * (std::sqrt(1.0f + a2_tan2) - 1.0f);
  }

  TESSERA_HD float g1(const vec3& w) const { return 1.0f / (1.0f + lambda(w)); }

  // Height-correlated masking-shadowing of the pair (Heitz 2014, eq. 99).
  TESSERA_HD float g2(const vec3& wo, const vec3& wi) const {
    return 1.0f / (1.0f + lambda(wo) + lambda(wi));
  }

  // Density of the normals visible from w (w.z > 0), per solid angle of m:
  // G1(w) max(0, w.m) D(m) / w.z.
  TESSERA_HD float visible_d(const vec3& w, const vec3& m) const {
    const float cos_wm = glm::dot(w, m);
    if (!(w.z > 0.0f) || cos_wm <= 0.0f) return 0.0f;
    return g1(w) * cos_wm * d(m) / w.z;
  }

  // A normal drawn from visible_d(w, .) for w.z > 0: stretch w to the unit-roughness
  // configuration, sample the projected hemisphere there (a disk, half of it squashed by
  // the visible fraction), and unstretch the normal.
  TESSERA_HD vec3 sample_visible(const vec3& w, float u1, float u2) const {
    const vec3 wh = glm::normalize(vec3(alpha_x * w.x, alpha_y * w.y, w.z));
    const float len2 = wh.x * wh.x + wh.y * wh.y;
    const vec3 t1 =
        len2 > 0.0f ? vec3(-wh.y, wh.x, 0.0f) / std::sqrt(len2) : vec3(1.0f, 0.0f, 0.0f);
    const vec3 t2 = glm::cross(wh, t1);
    const float r = std::sqrt(u1);
    float sin_phi, cos_phi;
    fast_sincos_turns(u2, sin_phi, cos_phi);
    const float p1 = r * cos_phi;
    float p2 = r * sin_phi;
    const float s = 0.5f * (1.0f + wh.z);
    p2 = (1.0f - s) * std::sqrt(glm::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const float pz = std::sqrt(glm::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    const vec3 nh = p1 * t1 + p2 * t2 + pz * wh;
    return glm::normalize(vec3(alpha_x * nh.x, alpha_y * nh.y, glm::max(1e-6f, nh.z)));
  }
};

// Mirror of `w` about unit `m`.
TESSERA_HD TESSERA_INLINE vec3 reflect_about(const vec3& w, const vec3& m) {
  return 2.0f * glm::dot(w, m) * m - w;
}

}  // namespace tessera
