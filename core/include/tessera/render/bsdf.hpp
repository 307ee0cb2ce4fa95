#pragma once
// The BSDF interface every material scatters through: sample, eval and pdf in a local
// shading frame (+z is the shading normal on the side the path arrives from; wo and wi
// both point away from the surface). Dispatch is a switch on the material's BsdfKind, so the
// same code runs on the CPU and, through nvcc, on the GPU, without virtual calls.
#include <cmath>
#include <cstdint>

#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"
#include "tessera/render/material.hpp"
#include "tessera/render/thin_film.hpp"

namespace tessera {

// Schlick's approximation of unpolarised Fresnel reflectance.
TESSERA_HD TESSERA_INLINE float schlick_reflectance(float cos_theta, float eta_ratio) {
  float r0 = (1.0f - eta_ratio) / (1.0f + eta_ratio);
  r0 *= r0;
  const float m = 1.0f - glm::clamp(cos_theta, 0.0f, 1.0f);
  return r0 + (1.0f - r0) * m * m * m * m * m;
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

// The solid-angle density of RayON's fuzzy-metal direction (sample_fuzzy_reflection) about the unit
// mirror direction `r` (before the below-surface cut): the direction of r + f b with b uniform in
// the unit ball. Along direction w the ball of radius f centred at r covers t in [t1, t2] with t^2
// - 2 t cos + 1 - f^2 = 0, and the density is the ball's volume along that ray, (t2^3 - t1^3) / 3,
// over the ball's volume. sin^2 comes from a cross product, not 1 - cos^2, so a narrow lobe keeps
// its precision.
TESSERA_HD TESSERA_INLINE float fuzzy_reflection_pdf(const vec3& r, const vec3& w, float f) {
  const float cos_theta = glm::dot(r, w);
  const vec3 c = glm::cross(r, w);
  const float disc = f * f - glm::dot(c, c);
  if (!(disc > 0.0f)) return 0.0f;
  const float root = std::sqrt(disc);
  const float t2 = cos_theta + root;
  if (!(t2 > 0.0f)) return 0.0f;
  const float t1 = glm::max(cos_theta - root, 0.0f);
  const float cubes = (t2 - t1) * (t2 * t2 + t2 * t1 + t1 * t1);
  return cubes / (4.0f * kPi * f * f * f);
}

enum BsdfLobe : std::uint32_t {
  kLobeNone = 0,
  kLobeReflection = 1u << 0,
  kLobeTransmission = 1u << 1,
  kLobeDiffuse = 1u << 2,
  kLobeGlossy = 1u << 3,
  kLobeSpecular = 1u << 4,  // a delta distribution: eval and pdf never see it
};

struct BsdfSample {
  vec3 wi{0.0f};
  vec3 f{0.0f};      // BSDF value; for a specular lobe, weight * pdf / |cos|
  float pdf = 0.0f;  // solid angle, or the discrete probability of a specular lobe
  std::uint32_t lobe = kLobeNone;

  TESSERA_HD bool valid() const { return lobe != kLobeNone && pdf > 0.0f; }
  TESSERA_HD bool specular() const { return (lobe & kLobeSpecular) != 0; }
  // f |cos| / pdf: what the path throughput is multiplied by.
  TESSERA_HD vec3 weight() const { return f * (std::fabs(wi.z) / pdf); }
};

// White fuzzy reflection (RayON's metal lobe) in the shading frame: the mirror direction
// plus `roughness` times a point in the unit ball (u3 its radius, u1 and u2 its direction);
// directions the perturbation sends below the surface are absorbed, as RayON does, so the
// lobe loses that energy. Roughness 0 is a perfect mirror.
TESSERA_HD inline BsdfSample sample_fuzzy_reflection(const vec3& wo, float roughness, float u3,
                                                     float u1, float u2) {
  BsdfSample s;
  const vec3 mirror(-wo.x, -wo.y, wo.z);
  if (roughness <= 0.0f) {
    s.wi = mirror;
    s.pdf = 1.0f;
    s.f = vec3(1.0f / mirror.z);
    s.lobe = kLobeReflection | kLobeSpecular;
    return s;
  }
  const vec3 ball = sample_uniform_sphere(u1, u2) * std::cbrt(u3);
  const vec3 r = mirror + roughness * ball;
  const float len2 = glm::dot(r, r);
  if (!(len2 > 0.0f)) return s;
  s.wi = r / std::sqrt(len2);
  if (s.wi.z <= 0.0f) return BsdfSample{};
  s.pdf = fuzzy_reflection_pdf(mirror, s.wi, roughness);
  if (!(s.pdf > 0.0f)) return BsdfSample{};
  s.f = vec3(s.pdf / s.wi.z);
  s.lobe = kLobeReflection | kLobeGlossy;
  return s;
}

// A specular pair: the mirror reflection with probability `r` (u below it), else the
// `transmitted` direction, each tinted by `tint` (glass; the virtual baseline's thin shell).
TESSERA_HD inline BsdfSample sample_specular_pair(const vec3& wo, float r, const vec3& transmitted,
                                                  const vec3& tint, float u) {
  BsdfSample s;
  if (u < r) {
    s.wi = vec3(-wo.x, -wo.y, wo.z);
    s.pdf = r;
    s.lobe = kLobeReflection | kLobeSpecular;
  } else {
    s.wi = transmitted;
    s.pdf = 1.0f - r;
    s.lobe = kLobeTransmission | kLobeSpecular;
  }
  s.f = tint * (s.pdf / std::fabs(s.wi.z));
  return s;
}

// One material's scattering at one hit. `eta` is the relative index of refraction
// n_transmitted / n_incident for the side the path arrives from.
struct Bsdf {
  BsdfKind kind = BsdfKind::kDiffuse;
  vec3 albedo{0.0f};
  float roughness = 0.0f;
  float eta = 1.5f;
  // Thin films (kThinDielectric): the same on both faces.
  float film_ior = 1.33f;
  float exterior_ior = 1.0f;
  float film_thickness_nm = 0.0f;

  TESSERA_HD static Bsdf of(const Material& m, bool front_face) {
    Bsdf b;
    b.kind = m.kind;
    b.albedo = m.albedo;
    b.roughness = m.roughness;
    b.eta = front_face ? m.ior : 1.0f / m.ior;
    b.film_ior = m.ior;
    b.exterior_ior = m.exterior_ior;
    b.film_thickness_nm = m.film_thickness_nm;
    return b;
  }

  // True when eval and pdf can be non-zero somewhere, so light sampling can help.
  TESSERA_HD bool has_non_specular() const {
    switch (kind) {
      case BsdfKind::kDiffuse:
      case BsdfKind::kCoated:
        return true;
      case BsdfKind::kConductor:
        return roughness > 0.0f;
      default:
        return false;
    }
  }

  TESSERA_HD BsdfSample sample(const vec3& wo, float u_lobe, float u1, float u2) const {
    BsdfSample s;
    if (wo.z <= 0.0f) return s;
    switch (kind) {
      case BsdfKind::kDiffuse:
        return sample_diffuse(u1, u2, albedo);
      case BsdfKind::kConductor:
        s = sample_fuzzy(wo, u_lobe, u1, u2);
        s.f *= albedo;
        return s;
      case BsdfKind::kCoated: {
        const float coat = schlick_reflectance(wo.z, 1.0f / eta_outside());
        // u_lobe picks the coat with probability `coat`, then is stretched back to [0, 1)
        // so the fuzzy lobe can use it.
        if (u_lobe < coat) {
          s = sample_fuzzy(wo, glm::min(u_lobe / coat, kOneMinusEpsilon), u1, u2);
          if (!s.valid()) return s;
          if (s.specular()) {
            s.pdf *= coat;
            s.f *= coat;
            return s;
          }
        } else {
          s.wi = sample_cosine_hemisphere(u1, u2);
          if (s.wi.z <= 0.0f) return BsdfSample{};
          s.lobe = kLobeReflection | kLobeDiffuse;
        }
        // A rough coat and the base are both continuous: f and pdf are the mixtures.
        s.f = eval(wo, s.wi);
        s.pdf = pdf(wo, s.wi);
        if (!(s.pdf > 0.0f)) return BsdfSample{};
        return s;
      }
      case BsdfKind::kDielectric: {
        // eta is n_t / n_i; refract() and Schlick take n_i / n_t.
        const float inv_eta = 1.0f / eta;
        const vec3 d = -wo;
        const vec3 n(0.0f, 0.0f, 1.0f);
        vec3 refracted(0.0f);  // unused on total internal reflection
        const bool can_refract = refract(d, n, inv_eta, refracted);
        const float r = can_refract ? schlick_reflectance(wo.z, inv_eta) : 1.0f;
        // RayON's glass: the albedo tints both, Fresnel only chooses between them.
        return sample_specular_pair(wo, r, refracted, albedo, u_lobe);
      }
      case BsdfKind::kThinDielectric:
        return sample_thin_film(wo, u_lobe);
      case BsdfKind::kEmitter:
      case BsdfKind::kConstant:  // unlit: the path tracer ends the path before sampling
      case BsdfKind::kShowNormals:
        return s;
    }
    return s;
  }

  TESSERA_HD vec3 eval(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return vec3(0.0f);
    switch (kind) {
      case BsdfKind::kDiffuse:
        return albedo * kInvPi;
      case BsdfKind::kConductor:
        if (roughness <= 0.0f) return vec3(0.0f);
        return albedo * (fuzzy_pdf(wo, wi) / wi.z);
      case BsdfKind::kCoated: {
        const float coat = schlick_reflectance(wo.z, 1.0f / eta_outside());
        vec3 f = (1.0f - coat) * kInvPi * albedo;
        if (roughness > 0.0f) f += vec3(coat * fuzzy_pdf(wo, wi) / wi.z);
        return f;
      }
      default:
        return vec3(0.0f);
    }
  }

  TESSERA_HD float pdf(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    switch (kind) {
      case BsdfKind::kDiffuse:
        return wi.z * kInvPi;
      case BsdfKind::kConductor:
        return roughness > 0.0f ? fuzzy_pdf(wo, wi) : 0.0f;
      case BsdfKind::kCoated: {
        const float coat = schlick_reflectance(wo.z, 1.0f / eta_outside());
        float p = (1.0f - coat) * wi.z * kInvPi;
        if (roughness > 0.0f) p += coat * fuzzy_pdf(wo, wi);
        return p;
      }
      default:
        return 0.0f;
    }
  }

 private:
  static constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

  // The coat faces air on both sides: its Fresnel term uses the material's index whichever
  // side is hit.
  TESSERA_HD float eta_outside() const { return eta >= 1.0f ? eta : 1.0f / eta; }

  TESSERA_HD static BsdfSample sample_diffuse(float u1, float u2, const vec3& albedo) {
    BsdfSample s;
    s.wi = sample_cosine_hemisphere(u1, u2);
    if (s.wi.z <= 0.0f) return s;
    s.pdf = s.wi.z * kInvPi;
    s.f = albedo * kInvPi;
    s.lobe = kLobeReflection | kLobeDiffuse;
    return s;
  }

  // A thin film reflects R (RGB, Airy) and transmits 1 - R straight on. The lobe is picked
  // by the channel average, and each lobe's weight divides by its probability, so every
  // channel keeps exactly R + (1 - R) = 1 in expectation.
  TESSERA_HD BsdfSample sample_thin_film(const vec3& wo, float u_lobe) const {
    const vec3 r = thin_film_reflectance(wo.z, exterior_ior, film_ior, film_thickness_nm);
    const float reflect = (r.x + r.y + r.z) * (1.0f / 3.0f);
    BsdfSample s;
    if (u_lobe < reflect) {
      s.wi = vec3(-wo.x, -wo.y, wo.z);
      s.pdf = reflect;
      s.f = r / s.wi.z;  // weight r / reflect
      s.lobe = kLobeReflection | kLobeSpecular;
    } else {
      s.wi = -wo;
      s.pdf = 1.0f - reflect;
      s.f = (vec3(1.0f) - r) / wo.z;  // weight (1 - r) / (1 - reflect)
      s.lobe = kLobeTransmission | kLobeSpecular;
    }
    return s;
  }

  TESSERA_HD float fuzzy_pdf(const vec3& wo, const vec3& wi) const {
    return fuzzy_reflection_pdf(vec3(-wo.x, -wo.y, wo.z), wi, roughness);
  }

  TESSERA_HD BsdfSample sample_fuzzy(const vec3& wo, float u3, float u1, float u2) const {
    return sample_fuzzy_reflection(wo, roughness, u3, u1, u2);
  }
};

}  // namespace tessera
