#pragma once
// The BSDF interface every material scatters through: sample, eval and pdf in a local
// shading frame (+z is the shading normal on the side the path arrives from; wo and wi
// both point away from the surface). Dispatch is a switch on the material's BsdfKind, so the
// same code runs on the CPU and, through nvcc, on the GPU, without virtual calls.
#include <cmath>
#include <cstdint>

#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"
#include "tessera/render/fresnel.hpp"
#include "tessera/render/material.hpp"
#include "tessera/render/microfacet.hpp"
#include "tessera/render/thin_film.hpp"

namespace tessera {

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

// A specular pair: the mirror reflection with probability `r` (u below it), else the
// `transmitted` direction, each tinted by `tint` (smooth glass).
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

// The tangent an anisotropic lobe's alpha_x runs along: cross(+y, n), around the world's +y
// axis (the circles of latitude of a sphere whose pole is +y; along x on a surface facing
// +z), so brushing is continuous over spheres and consistent over meshes, which carry no
// tangents. Where the normal is +-y itself, along x.
TESSERA_HD TESSERA_INLINE vec3 anisotropy_tangent(const vec3& n) {
  const vec3 t(n.z, 0.0f, -n.x);  // cross(+y, n)
  if (t.x * t.x + t.z * t.z < 1e-8f) return vec3(1.0f, 0.0f, 0.0f);
  return t;
}

// One material's scattering at one hit. `eta` is the relative index of refraction
// n_transmitted / n_incident for the side the path arrives from.
struct Bsdf {
  BsdfKind kind = BsdfKind::kDiffuse;
  vec3 albedo{0.0f};
  float eta = 1.5f;
  // Thin films (kThinDielectric): the same on both faces.
  float film_ior = 1.33f;
  float exterior_ior = 1.0f;
  float film_thickness_nm = 0.0f;
  GgxDistribution ggx{};
  bool complex_fresnel = false;
  vec3 conductor_eta{1.0f};
  vec3 conductor_k{0.0f};

  TESSERA_HD static Bsdf of(const Material& m, bool front_face) {
    return of(m, front_face, m.albedo);
  }
  // `albedo_here`: the material's albedo at the hit (a pattern varies it).
  TESSERA_HD static Bsdf of(const Material& m, bool front_face, const vec3& albedo_here) {
    Bsdf b;
    b.kind = m.kind;
    b.albedo = albedo_here;
    b.eta = front_face ? m.ior : 1.0f / m.ior;
    b.film_ior = m.ior;
    b.exterior_ior = m.exterior_ior;
    b.film_thickness_nm = m.film_thickness_nm;
    b.ggx = GgxDistribution{m.alpha_x, m.alpha_y};
    b.complex_fresnel = m.complex_fresnel;
    b.conductor_eta = m.eta;
    b.conductor_k = m.k;
    // Glass tints what it lets in, once per entry, so a closed object is tinted once per
    // pass and a white one is lossless; leaving, and reflecting, it tints nothing.
    if (m.kind == BsdfKind::kDielectric && !front_face) b.albedo = vec3(1.0f);
    return b;
  }

  // True when eval and pdf can be non-zero somewhere, so light sampling can help.
  TESSERA_HD bool has_non_specular() const {
    switch (kind) {
      case BsdfKind::kDiffuse:
      case BsdfKind::kCoated:
        return true;
      case BsdfKind::kConductor:
        return !ggx.effectively_smooth();
      case BsdfKind::kDielectric:
        return rough_dielectric();
      default:
        return false;
    }
  }

  // True when eval and pdf can be non-zero for directions below the surface.
  TESSERA_HD bool has_glossy_transmission() const {
    return kind == BsdfKind::kDielectric && rough_dielectric();
  }

  // True when the lobe depends on the tangent's direction: the shading frame's tangent must
  // then be the surface's (anisotropic_tangent), not an arbitrary one.
  TESSERA_HD bool anisotropic() const {
    return kind == BsdfKind::kConductor && ggx.alpha_x != ggx.alpha_y;
  }

  // sample, eval and pdf take the Lambertian case inline (the most common vertex by far)
  // and call the general forms for the others: called out of line for every kind, each
  // call spilled and reloaded the caller's registers around a few multiplies.
  TESSERA_HD TESSERA_FORCE_INLINE BsdfSample sample(const vec3& wo, float u_lobe, float u1,
                                                    float u2) const {
    if (kind == BsdfKind::kDiffuse)
      return wo.z <= 0.0f ? BsdfSample{} : sample_diffuse(u1, u2, albedo);
    return sample_any(wo, u_lobe, u1, u2);
  }
  TESSERA_HD TESSERA_FORCE_INLINE vec3 eval(const vec3& wo, const vec3& wi) const {
    if (kind == BsdfKind::kDiffuse)
      return wo.z <= 0.0f || wi.z <= 0.0f ? vec3(0.0f) : albedo * kInvPi;
    return eval_any(wo, wi);
  }
  TESSERA_HD TESSERA_FORCE_INLINE float pdf(const vec3& wo, const vec3& wi) const {
    if (kind == BsdfKind::kDiffuse) return wo.z <= 0.0f || wi.z <= 0.0f ? 0.0f : wi.z * kInvPi;
    return pdf_any(wo, wi);
  }

 private:
  // The general forms of sample, eval and pdf, for every kind.
  TESSERA_HD BsdfSample sample_any(const vec3& wo, float u_lobe, float u1, float u2) const {
    BsdfSample s;
    if (wo.z <= 0.0f) return s;
    switch (kind) {
      case BsdfKind::kDiffuse:
        return sample_diffuse(u1, u2, albedo);
      case BsdfKind::kConductor:
        return sample_conductor(wo, u1, u2);
      case BsdfKind::kCoated: {
        const float coat = coat_reflectance(wo);
        // u_lobe picks the coat with probability `coat`.
        if (u_lobe < coat) {
          s = sample_white_ggx(wo, u1, u2);
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
        if (rough_dielectric()) return sample_rough_dielectric(wo, u_lobe, u1, u2);
        // eta is n_t / n_i; refract() takes n_i / n_t.
        const vec3 n(0.0f, 0.0f, 1.0f);
        vec3 refracted(0.0f);  // unused on total internal reflection (r = 1)
        refract(-wo, n, 1.0f / eta, refracted);
        const float r = fresnel_dielectric(wo.z, eta);
        s = sample_specular_pair(wo, r, refracted, vec3(1.0f), u_lobe);
        if ((s.lobe & kLobeTransmission) != 0) s.f *= albedo;
        return s;
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

  TESSERA_HD vec3 eval_any(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f) return vec3(0.0f);
    if (kind == BsdfKind::kDielectric) return eval_rough_dielectric(wo, wi);
    if (wi.z <= 0.0f) return vec3(0.0f);
    switch (kind) {
      case BsdfKind::kDiffuse:
        return albedo * kInvPi;
      case BsdfKind::kConductor: {
        vec3 m;
        if (ggx.effectively_smooth() || !reflection_half_vector(wo, wi, m)) return vec3(0.0f);
        return conductor_fresnel(glm::dot(wo, m)) * white_ggx_f(wo, wi, m);
      }
      case BsdfKind::kCoated: {
        const float coat = coat_reflectance(wo);
        vec3 f = (1.0f - coat) * kInvPi * albedo;
        vec3 m;
        if (!ggx.effectively_smooth() && reflection_half_vector(wo, wi, m))
          f += vec3(coat * white_ggx_f(wo, wi, m));
        return f;
      }
      default:
        return vec3(0.0f);
    }
  }

  TESSERA_HD float pdf_any(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f) return 0.0f;
    if (kind == BsdfKind::kDielectric) return pdf_rough_dielectric(wo, wi);
    if (wi.z <= 0.0f) return 0.0f;
    switch (kind) {
      case BsdfKind::kDiffuse:
        return wi.z * kInvPi;
      case BsdfKind::kConductor: {
        vec3 m;
        if (ggx.effectively_smooth() || !reflection_half_vector(wo, wi, m)) return 0.0f;
        return white_ggx_pdf(wo, m);
      }
      case BsdfKind::kCoated: {
        const float coat = coat_reflectance(wo);
        float p = (1.0f - coat) * wi.z * kInvPi;
        vec3 m;
        if (!ggx.effectively_smooth() && reflection_half_vector(wo, wi, m))
          p += coat * white_ggx_pdf(wo, m);
        return p;
      }
      default:
        return 0.0f;
    }
  }

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
  // with thin_film_reflect_probability, and each lobe's weight divides by its probability,
  // so every channel keeps exactly R + (1 - R) = 1 in expectation.
  TESSERA_HD BsdfSample sample_thin_film(const vec3& wo, float u_lobe) const {
    const vec3 r = thin_film_reflectance(wo.z, exterior_ior, film_ior, film_thickness_nm);
    const float reflect = thin_film_reflect_probability(r);
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

  // Glass with a GGX lobe; an index of 1 is no interface at all, so it stays smooth (a
  // straight pass-through, which the generalised half vector cannot express).
  TESSERA_HD bool rough_dielectric() const { return !ggx.effectively_smooth() && eta != 1.0f; }

  // The conductor's reflectance at a microfacet seen at cos_i: the albedo alone, or the
  // albedo times the complex-index Fresnel term.
  TESSERA_HD vec3 conductor_fresnel(float cos_i) const {
    if (!complex_fresnel) return albedo;
    return albedo * fresnel_conductor(cos_i, conductor_eta, conductor_k);
  }

  // White GGX reflection (Fresnel 1): a visible normal, the mirror direction about it; the
  // weight f cos / pdf is G2 / G1(wo) <= 1. Smooth: a mirror with weight 1. The conductor
  // multiplies it by its Fresnel term, the coat picks it with its own.
  TESSERA_HD BsdfSample sample_white_ggx(const vec3& wo, float u1, float u2) const {
    BsdfSample s;
    if (ggx.effectively_smooth()) {
      s.wi = vec3(-wo.x, -wo.y, wo.z);
      s.pdf = 1.0f;
      s.f = vec3(1.0f / wo.z);
      s.lobe = kLobeReflection | kLobeSpecular;
      return s;
    }
    const vec3 m = ggx.sample_visible(wo, u1, u2);
    const float cos_om = glm::dot(wo, m);
    if (!(cos_om > 0.0f)) return s;
    s.wi = reflect_about(wo, m);
    if (s.wi.z <= 0.0f) return BsdfSample{};
    s.pdf = white_ggx_pdf(wo, m);
    if (!(s.pdf > 0.0f)) return BsdfSample{};
    s.f = vec3(white_ggx_f(wo, s.wi, m));
    s.lobe = kLobeReflection | kLobeGlossy;
    return s;
  }

  // D G2 / (4 cos_o cos_i) and the reflection's density D_visible / (4 wo.m), for the
  // half vector m of wo and wi (both above the surface).
  TESSERA_HD float white_ggx_f(const vec3& wo, const vec3& wi, const vec3& m) const {
    return ggx.d(m) * ggx.g2(wo, wi) / (4.0f * wo.z * wi.z);
  }
  TESSERA_HD float white_ggx_pdf(const vec3& wo, const vec3& m) const {
    return ggx.visible_d(wo, m) / (4.0f * glm::dot(wo, m));
  }
  TESSERA_HD static bool reflection_half_vector(const vec3& wo, const vec3& wi, vec3& m) {
    const vec3 h = wo + wi;
    const float len2 = glm::dot(h, h);
    if (!(len2 > 0.0f)) return false;
    m = h / std::sqrt(len2);
    return true;
  }

  // GGX conductor: white GGX reflection times the Fresnel term at the sampled microfacet
  // (at the macro normal when smooth).
  TESSERA_HD BsdfSample sample_conductor(const vec3& wo, float u1, float u2) const {
    BsdfSample s = sample_white_ggx(wo, u1, u2);
    if (!s.valid()) return s;
    const float cos_om = s.specular() ? wo.z : glm::dot(wo, glm::normalize(wo + s.wi));
    s.f *= conductor_fresnel(cos_om);
    return s;
  }

  // The clear coat's share: the exact Fresnel reflectance of its interface (air on both
  // sides of a coat, whichever side is hit) at the macro normal. The base receives the
  // rest; a coat lobe of albedo <= 1 and a base of albedo <= 1 mix to <= 1.
  TESSERA_HD float coat_reflectance(const vec3& wo) const {
    return fresnel_dielectric(wo.z, eta_outside());
  }

  // Rough glass (Walter et al. 2007, sampled through the visible normals): a microfacet
  // normal m, then reflection about it with probability F(wo.m), else refraction through
  // it. Each lobe's weight f |cos| / pdf is G2 / G1(wo) (times the tint on entry), so the
  // lobe never returns more than it receives. Like the smooth glass, the transmitted
  // radiance is not scaled by 1 / eta^2: on a closed object the factors of entry and exit
  // cancel.
  TESSERA_HD BsdfSample sample_rough_dielectric(const vec3& wo, float u_lobe, float u1,
                                                float u2) const {
    BsdfSample s;
    const vec3 m = ggx.sample_visible(wo, u1, u2);
    const float cos_om = glm::dot(wo, m);
    if (!(cos_om > 0.0f)) return s;
    const float r = fresnel_dielectric(cos_om, eta);
    if (u_lobe < r) {
      s.wi = reflect_about(wo, m);
      if (s.wi.z <= 0.0f) return BsdfSample{};
      s.lobe = kLobeReflection | kLobeGlossy;
    } else {
      vec3 refracted(0.0f);
      if (!refract(-wo, m, 1.0f / eta, refracted)) return s;  // r = 1 there: not reached
      s.wi = refracted;
      if (s.wi.z >= 0.0f) return BsdfSample{};
      s.lobe = kLobeTransmission | kLobeGlossy;
    }
    s.f = eval_rough_dielectric(wo, s.wi);
    s.pdf = pdf_rough_dielectric(wo, s.wi);
    if (!(s.pdf > 0.0f)) return BsdfSample{};
    return s;
  }

  // The microfacet normal a pair of directions shares: the half vector for a reflection,
  // the generalised half vector wo + eta wi for a refraction, on the +z side. False when
  // the pair cannot be connected by one microfacet facing both.
  TESSERA_HD bool dielectric_half_vector(const vec3& wo, const vec3& wi, vec3& m) const {
    const bool reflection = wi.z > 0.0f;
    vec3 h = reflection ? wo + wi : wo + eta * wi;
    const float len2 = glm::dot(h, h);
    if (!(len2 > 0.0f)) return false;
    h /= std::sqrt(len2);
    if (h.z < 0.0f) h = -h;
    // Both directions must see the microfacet from the side their macro side says.
    if (glm::dot(h, wo) <= 0.0f) return false;
    if (reflection ? glm::dot(h, wi) <= 0.0f : glm::dot(h, wi) >= 0.0f) return false;
    m = h;
    return true;
  }

  TESSERA_HD vec3 eval_rough_dielectric(const vec3& wo, const vec3& wi) const {
    if (!rough_dielectric() || wi.z == 0.0f) return vec3(0.0f);
    vec3 m;
    if (!dielectric_half_vector(wo, wi, m)) return vec3(0.0f);
    const float cos_om = glm::dot(wo, m);
    const float cos_im = glm::dot(wi, m);
    const float r = fresnel_dielectric(cos_om, eta);
    const float dg = ggx.d(m) * ggx.g2(wo, wi);  // Lambda depends on wi.z^2 only
    if (wi.z > 0.0f) return vec3(r * dg / (4.0f * wo.z * wi.z));
    const float denom = cos_im + cos_om / eta;
    const float t = (1.0f - r) * dg * std::fabs(cos_im * cos_om / (wo.z * wi.z * denom * denom));
    return albedo * t;
  }

  TESSERA_HD float pdf_rough_dielectric(const vec3& wo, const vec3& wi) const {
    if (!rough_dielectric() || wi.z == 0.0f) return 0.0f;
    vec3 m;
    if (!dielectric_half_vector(wo, wi, m)) return 0.0f;
    const float cos_om = glm::dot(wo, m);
    const float r = fresnel_dielectric(cos_om, eta);
    const float visible = ggx.visible_d(wo, m);
    if (wi.z > 0.0f) return r * visible / (4.0f * cos_om);
    const float cos_im = glm::dot(wi, m);
    const float denom = cos_im + cos_om / eta;
    return (1.0f - r) * visible * std::fabs(cos_im) / (denom * denom);
  }
};

}  // namespace tessera
