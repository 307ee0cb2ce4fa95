#pragma once
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

// The BSDF families the renderer evaluates. Scene material types map onto these; see
// make_material() for the mapping and what each approximates.
enum class BsdfKind : std::uint32_t {
  kDiffuse = 0,         // Lambertian
  kConductor = 1,       // GGX microfacet conductor (a mirror when smooth)
  kDielectric = 2,      // glass: smooth, or rough (GGX, Walter et al. 2007)
  kThinDielectric = 3,  // thin shell (soap film): reflection or straight transmission
  kCoated = 4,          // clear coat (exact Fresnel, GGX) over a diffuse base
  kEmitter = 5,         // emits, does not scatter
};

struct Material {
  BsdfKind kind = BsdfKind::kDiffuse;
  vec3 albedo{0.8f};
  vec3 emission{0.0f};
  float roughness = 0.0f;
  float ior = 1.5f;
  float opacity = 1.0f;  // for the transparency integrator only
  // GGX roughness along the shading frame's tangent and bitangent (conductors, glass and
  // clear coats);
  // make_material maps the scene's roughness and anisotropy onto them.
  float alpha_x = 0.0f;
  float alpha_y = 0.0f;
  // Conductors: Fresnel from the complex index eta + i k per channel (times albedo) when
  // set, else the albedo alone (RayON's metal and rough_mirror).
  bool complex_fresnel = false;
  vec3 eta{1.0f};
  vec3 k{0.0f};
  // Glass: absorption coefficient per unit length inside (Beer's law); 0 = clear.
  vec3 absorption{0.0f};

  TESSERA_HD bool absorbs() const {
    return absorption.x > 0.0f || absorption.y > 0.0f || absorption.z > 0.0f;
  }

  TESSERA_HD bool emissive() const {
    return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
  }
};

}  // namespace tessera
