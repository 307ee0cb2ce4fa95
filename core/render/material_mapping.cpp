#include "tessera/render/material_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tessera {

namespace {

struct ComplexIndex {
  vec3 eta;
  vec3 k;
};

// Measured complex indices of refraction (n + i k) of RayON's metal presets, per RGB channel
// read at the tabulated wavelengths nearest 650, 550 and 450 nm (652.5, 551.0 and 450.9 nm).
// Gold, silver, copper and aluminium: the spectra pbrt ships (src/pbrt/util/spectrum.cpp,
// metal-Au/Ag/Cu/Al-eta and -k, from Palik's Handbook of Optical Constants of Solids).
// Chromium: Palik's data as Mitsuba ships it (data/ior/Cr.eta.spd, Cr.k.spd), linearly
// interpolated to 650, 550 and 450 nm.
bool metal_preset(const std::string& preset, ComplexIndex& out) {
  if (preset == "gold") {
    out = {vec3(0.166f, 0.3455f, 1.5021f), vec3(3.150f, 2.7306f, 1.8759f)};
  } else if (preset == "silver") {
    out = {vec3(0.140f, 0.1244f, 0.1511f), vec3(4.150f, 3.3481f, 2.4788f)};
  } else if (preset == "copper") {
    out = {vec3(0.214f, 0.9504f, 1.1653f), vec3(3.670f, 2.5765f, 2.3976f)};
  } else if (preset == "aluminium" || preset == "aluminum") {
    out = {vec3(1.490f, 0.9630f, 0.6203f), vec3(7.820f, 6.7000f, 5.4800f)};
  } else if (preset == "chromium") {
    out = {vec3(3.638f, 3.116f, 1.928f), vec3(4.364f, 4.423f, 4.168f)};
  } else {
    return false;
  }
  return true;
}

// The conductor's GGX roughness. RayON's anisotropic_metal is GGX already: alpha =
// roughness^2, stretched by aspect = sqrt(1 - 0.9 anisotropy) to alpha / aspect along the
// tangent and alpha * aspect along the bitangent (as RayON's renderer does, so a brushed
// metal keeps its highlight). RayON's metal and rough_mirror perturb the mirror by roughness
// times a point in the unit ball; GGX with alpha = roughness / 2 has about that lobe width
// (the half vector moves half as far as the reflected direction), and is the mapping
// bench/peers gives Cycles for the same materials.
void conductor_roughness(const MaterialDesc& desc, Material& m) {
  m.roughness_mapping = desc.type == MaterialType::kAnisotropicMetal ? RoughnessMapping::kSquared
                                                                     : RoughnessMapping::kHalf;
  m.anisotropy_aspect =
      std::sqrt(std::max(1e-4f, 1.0f - 0.9f * static_cast<float>(desc.anisotropy)));
}

}  // namespace

Material make_material(const MaterialDesc& desc) {
  Material m;
  m.albedo = vec3(desc.albedo);
  m.emission = vec3(desc.emitted_radiance());
  m.roughness = static_cast<float>(desc.roughness);
  m.ior = static_cast<float>(desc.refractive_index);
  switch (desc.type) {
    case MaterialType::kLambertian:
      m.kind = BsdfKind::kDiffuse;
      break;
    case MaterialType::kLight:
      m.kind = BsdfKind::kEmitter;
      break;
    case MaterialType::kMetal:
    case MaterialType::kRoughMirror:
    case MaterialType::kAnisotropicMetal: {
      // Fresnel: the measured index of a preset or of eta and k, tinted by the albedo;
      // without either, the albedo alone at every angle, as RayON renders its metals.
      m.kind = BsdfKind::kConductor;
      conductor_roughness(desc, m);
      ComplexIndex index{};
      if (metal_preset(desc.preset, index)) {
        m.complex_fresnel = true;
        m.eta = index.eta;
        m.k = index.k;
      } else if (desc.eta != glm::dvec3(0.0)) {
        m.complex_fresnel = true;
        m.eta = vec3(desc.eta);
        m.k = vec3(desc.k);
      }
      break;
    }
    case MaterialType::kGlass: {
      // Rough glass is GGX with alpha = roughness^2 (Cycles' and Disney's convention).
      m.kind = BsdfKind::kDielectric;
      m.roughness_mapping = RoughnessMapping::kSquared;
      // Beer's law: T = exp(-sigma d) for the given share T left after distance d.
      m.absorption = vec3(-glm::log(desc.transmittance) / desc.transmittance_distance);
      break;
    }
    case MaterialType::kThinFilm:
      // RayON's thin_film: refractive_index is the medium around the film.
      m.kind = BsdfKind::kThinDielectric;
      m.ior = static_cast<float>(desc.film_ior);
      m.exterior_ior = static_cast<float>(desc.refractive_index);
      m.film_thickness_nm = static_cast<float>(desc.film_thickness);
      break;
    case MaterialType::kClearCoat:
      // RayON's coat perturbs its mirror like rough_mirror: the same alpha = roughness / 2.
      m.kind = BsdfKind::kCoated;
      m.roughness_mapping = RoughnessMapping::kHalf;
      break;
    case MaterialType::kMirror:
      // RayON's mirror: the reflection direction, tinted by albedo, whatever the roughness.
      m.kind = BsdfKind::kConductor;
      m.roughness = 0.0f;
      break;
    case MaterialType::kConstant:
      m.kind = BsdfKind::kConstant;
      break;
    case MaterialType::kShowNormals:
      m.kind = BsdfKind::kShowNormals;
      break;
  }
  m.set_roughness(m.roughness);
  if (desc.pattern) {
    const PatternDesc& p = *desc.pattern;
    if (p.type == "fibonacci_dots") m.pattern.type = PatternType::kFibonacciDots;
    if (p.type == "checkerboard") m.pattern.type = PatternType::kCheckerboard;
    if (p.type == "stripes") m.pattern.type = PatternType::kStripes;
    m.pattern.color = vec3(p.color);
    m.pattern.dot_count = p.dot_count;
    m.pattern.cos_dot_radius = static_cast<float>(std::cos(p.dot_radius));
  }
  // Transmissive surfaces stay faintly visible in the transparency view.
  const bool transmissive = m.kind == BsdfKind::kDielectric || m.kind == BsdfKind::kThinDielectric;
  m.opacity = static_cast<float>(transmissive ? std::max(0.1, 1.0 - desc.transmission)
                                              : 1.0 - desc.transmission);
  return m;
}

}  // namespace tessera
