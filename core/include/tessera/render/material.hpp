#pragma once
#include <cstdint>

#include "tessera/math/vec.hpp"
#include "tessera/render/pattern.hpp"

namespace tessera {

// The BSDF families the renderer evaluates. Scene material types map onto these; see
// make_material() for the mapping and what each approximates.
enum class BsdfKind : std::uint32_t {
  kDiffuse = 0,         // Lambertian
  kConductor = 1,       // GGX microfacet conductor (a mirror when smooth)
  kDielectric = 2,      // glass: smooth, or rough (GGX, Walter et al. 2007)
  kThinDielectric = 3,  // thin film (soap bubble): Airy reflectance or straight transmission
  kCoated = 4,          // clear coat (exact Fresnel, GGX) over a diffuse base
  kEmitter = 5,         // emits, does not scatter
  // Unlit (RayON's debugging materials): the path ends at the surface and returns a colour
  // that no light affects. Not lights: nothing samples them, but a path that hits one sees
  // its colour, as in RayON.
  kConstant = 6,     // the albedo
  kShowNormals = 7,  // the shading normal facing the ray, mapped from [-1, 1] to [0, 1]
};

// How a material's roughness becomes its GGX alphas (see make_material for why each).
enum class RoughnessMapping : std::uint32_t {
  kNone = 0,     // smooth whatever the roughness (mirror), or no microfacet lobe
  kHalf = 1,     // alpha = roughness / 2: RayON's metal, rough_mirror and clear coat
  kSquared = 2,  // alpha = roughness^2: anisotropic_metal and glass
};

struct Material {
  BsdfKind kind = BsdfKind::kDiffuse;
  vec3 albedo{0.8f};
  vec3 emission{0.0f};
  float roughness = 0.0f;
  float ior = 1.5f;
  float opacity = 1.0f;  // for the transparency integrator only
  // Thin films: the film's thickness and the index of the medium on both its sides (`ior`
  // is the film's).
  float film_thickness_nm = 0.0f;
  float exterior_ior = 1.0f;
  MaterialPattern pattern;  // varies the albedo over the surface (RayON's pattern)
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
  RoughnessMapping roughness_mapping = RoughnessMapping::kNone;
  float anisotropy_aspect = 1.0f;  // alpha_x = alpha / aspect, alpha_y = alpha * aspect
  // Indices into SceneView::textures giving the albedo or the roughness at each hit; -1: the
  // constants above.
  std::int32_t albedo_texture = -1;
  std::int32_t roughness_texture = -1;
  // RayON's displaced_sphere: the strength of its golf-ball dimples on the shading normal
  // (render/golf_dimples.hpp); 0: none. The renderer gives each displaced sphere a copy of
  // its material with this set.
  float golf_dimples = 0.0f;

  // Sets the GGX alphas from a roughness in [0, 1], as the material's mapping says: once
  // from the scene's value, and again per hit from a roughness texture.
  TESSERA_HD void set_roughness(float r) {
    roughness = r;
    const float alpha = roughness_mapping == RoughnessMapping::kHalf      ? 0.5f * r
                        : roughness_mapping == RoughnessMapping::kSquared ? r * r
                                                                          : 0.0f;
    alpha_x = alpha / anisotropy_aspect;
    alpha_y = alpha * anisotropy_aspect;
  }

  TESSERA_HD bool absorbs() const {
    return absorption.x > 0.0f || absorption.y > 0.0f || absorption.z > 0.0f;
  }

  TESSERA_HD bool emissive() const {
    return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
  }
  TESSERA_HD bool unlit() const {
    return kind == BsdfKind::kConstant || kind == BsdfKind::kShowNormals;
  }
  // The colour an unlit material shows: its albedo at the hit (`albedo_here`: patterns
  // vary it), or for show_normals `facing_normal`, the unit shading normal on the side the
  // ray arrives from (RayON's hit normal).
  TESSERA_HD vec3 unlit_color(const vec3& albedo_here, const vec3& facing_normal) const {
    return kind == BsdfKind::kShowNormals ? 0.5f * (facing_normal + vec3(1.0f)) : albedo_here;
  }
};

}  // namespace tessera
