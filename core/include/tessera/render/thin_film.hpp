#pragma once
// Thin-film interference (soap bubbles, oil slicks): the Airy reflectance of a dielectric
// film of thickness d and index n1 between media n0 (the side light arrives from) and n2,
// summing every beam reflected between the film's two faces with its phase. RGB channels
// take one representative wavelength each, RayON's 650, 550 and 450 nm.
#include <cmath>

#include "tessera/math/vec.hpp"

namespace tessera {

TESSERA_HD TESSERA_INLINE float thin_film_wavelength_nm(int channel) {
  return channel == 0 ? 650.0f : channel == 1 ? 550.0f : 450.0f;
}

// Fresnel amplitude reflection coefficients of one interface for s and p polarisation,
// from index n_i (cosine cos_i) into n_t (cosine cos_t). The signs matter: they carry
// the half-wave phase shift of reflection off a denser medium.
struct FresnelAmplitudes {
  float s, p;
};
TESSERA_HD TESSERA_INLINE FresnelAmplitudes fresnel_amplitudes(float n_i, float cos_i, float n_t,
                                                               float cos_t) {
  return {(n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t),
          (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t)};
}

// Airy's sum for one polarisation: reflected amplitudes r01 (entering the film) and r12
// (its back face), round-trip phase delta. Lossless films transmit the rest, 1 - R.
TESSERA_HD TESSERA_INLINE float airy_sum(float r01, float r12, float cos_delta) {
  const float cross = 2.0f * r01 * r12 * cos_delta;
  const float denominator = 1.0f + r01 * r01 * r12 * r12 + cross;
  return glm::clamp((r01 * r01 + r12 * r12 + cross) / denominator, 0.0f, 1.0f);
}

// Unpolarised reflectance of the film at one wavelength; `cos_outside` is the cosine of
// the angle of incidence in n0. Total internal reflection at either face reflects all.
TESSERA_HD inline float airy_reflectance(float cos_outside, float n0, float n1, float n2,
                                         float thickness_nm, float wavelength_nm) {
  const float cos0 = glm::clamp(cos_outside, 0.0f, 1.0f);
  const float sin2_0 = 1.0f - cos0 * cos0;
  const float sin2_1 = (n0 / n1) * (n0 / n1) * sin2_0;
  const float sin2_2 = (n0 / n2) * (n0 / n2) * sin2_0;
  if (sin2_1 >= 1.0f || sin2_2 >= 1.0f) return 1.0f;
  const float cos1 = std::sqrt(1.0f - sin2_1);
  const float cos2 = std::sqrt(1.0f - sin2_2);
  const FresnelAmplitudes front = fresnel_amplitudes(n0, cos0, n1, cos1);
  const FresnelAmplitudes back = fresnel_amplitudes(n1, cos1, n2, cos2);
  // Round-trip optical path difference inside the film, as a phase.
  const float delta = 4.0f * kPi * n1 * thickness_nm * cos1 / wavelength_nm;
  const float cos_delta = std::cos(delta);
  return 0.5f * (airy_sum(front.s, back.s, cos_delta) + airy_sum(front.p, back.p, cos_delta));
}

// A free-standing film (the same medium n_outside on both sides, as a bubble's wall) per
// RGB channel.
TESSERA_HD inline vec3 thin_film_reflectance(float cos_outside, float n_outside, float n_film,
                                             float thickness_nm) {
  vec3 r;
  for (int c = 0; c < 3; ++c)
    r[c] = airy_reflectance(cos_outside, n_outside, n_film, n_outside, thickness_nm,
                            thin_film_wavelength_nm(c));
  return r;
}

// The probability of picking a film's reflection lobe for reflectance `r`: its largest
// channel. Each channel's weight is then r / max(r) <= 1 for reflection and
// (1 - r) / (1 - max(r)) for transmission, both near 1. Picking by the channels' mean let a
// channel that reflects several times the mean return that multiple of the light: the
// light's coloured reflections in soap bubbles, found by BSDF paths alone, were fireflies
// holding 80% of the error of RayON's 11_soap_bubbles.
TESSERA_HD TESSERA_INLINE float thin_film_reflect_probability(const vec3& r) {
  return glm::max(r.x, glm::max(r.y, r.z));
}

}  // namespace tessera
