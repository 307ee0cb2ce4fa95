#include "tessera/render/material_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tessera {

namespace {

// Normal-incidence colours of RayON's metal presets.
vec3 metal_preset_color(const std::string& preset, const vec3& fallback) {
  if (preset == "silver") return vec3(0.97f, 0.96f, 0.91f);
  if (preset == "gold") return vec3(1.00f, 0.78f, 0.34f);
  if (preset == "copper") return vec3(0.95f, 0.64f, 0.54f);
  if (preset == "aluminium" || preset == "aluminum") return vec3(0.91f, 0.92f, 0.92f);
  return fallback;
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
      m.kind = BsdfKind::kConductor;
      break;
    case MaterialType::kAnisotropicMetal:
      // Anisotropy is approximated as isotropic roughness for now.
      m.kind = BsdfKind::kConductor;
      m.albedo = metal_preset_color(desc.preset, m.albedo);
      break;
    case MaterialType::kGlass:
      m.kind = BsdfKind::kDielectric;
      break;
    case MaterialType::kThinFilm:
      // RayON's thin_film: refractive_index is the medium around the film.
      m.kind = BsdfKind::kThinDielectric;
      m.ior = static_cast<float>(desc.film_ior);
      m.exterior_ior = static_cast<float>(desc.refractive_index);
      m.film_thickness_nm = static_cast<float>(desc.film_thickness);
      break;
    case MaterialType::kClearCoat:
      m.kind = BsdfKind::kCoated;
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
