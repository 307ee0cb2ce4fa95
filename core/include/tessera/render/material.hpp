#pragma once
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

// The BSDF families the renderer evaluates. Scene material types map onto these; see
// make_material() for the mapping and what each approximates.
enum class BsdfKind : std::uint32_t {
  kDiffuse = 0,         // Lambertian
  kConductor = 1,       // mirror with roughness-scaled perturbation of the reflection
  kDielectric = 2,      // smooth glass: Fresnel-weighted reflection or refraction
  kThinDielectric = 3,  // thin shell (soap film): reflection or straight transmission
  kCoated = 4,          // clear coat over a diffuse base
  kEmitter = 5,         // emits, does not scatter
};

struct Material {
  BsdfKind kind = BsdfKind::kDiffuse;
  vec3 albedo{0.8f};
  vec3 emission{0.0f};
  float roughness = 0.0f;
  float ior = 1.5f;
  float opacity = 1.0f;  // for the transparency integrator only

  TESSERA_HD bool emissive() const {
    return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
  }
};

}  // namespace tessera
