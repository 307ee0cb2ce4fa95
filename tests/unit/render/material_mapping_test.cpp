// make_material for the physically based materials: each conductor type's GGX roughness
// (RayON's anisotropic mapping, the fuzz-equivalent one for metal and rough_mirror), the
// measured presets' normal-incidence colours, explicit eta and k, and rough glass.
#include <gtest/gtest.h>

#include <cmath>

#include "tessera/render/fresnel.hpp"
#include "tessera/render/material_mapping.hpp"

namespace tessera {
namespace {

MaterialDesc desc(MaterialType type, double roughness, double anisotropy = 0.0) {
  MaterialDesc d;
  d.type = type;
  apply_type_defaults(d);
  d.roughness = roughness;
  d.anisotropy = anisotropy;
  return d;
}

TEST(MaterialMapping, ConductorRoughness) {
  const Material metal = make_material(desc(MaterialType::kRoughMirror, 0.2));
  EXPECT_EQ(metal.kind, BsdfKind::kConductor);
  EXPECT_FLOAT_EQ(metal.alpha_x, 0.1f);
  EXPECT_FLOAT_EQ(metal.alpha_y, 0.1f);
  EXPECT_FALSE(metal.complex_fresnel);  // RayON's metal: the albedo alone
  // RayON: alpha = r^2, stretched by sqrt(1 - 0.9 a).
  const Material brushed = make_material(desc(MaterialType::kAnisotropicMetal, 0.5, 0.8));
  const float aspect = std::sqrt(1.0f - 0.72f);
  EXPECT_FLOAT_EQ(brushed.alpha_x, 0.25f / aspect);
  EXPECT_FLOAT_EQ(brushed.alpha_y, 0.25f * aspect);
  const Material mirror = make_material(desc(MaterialType::kMetal, 0.0));
  EXPECT_EQ(mirror.alpha_x, 0.0f);
}

// Normal-incidence reflectance ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) of each preset: the
// metals' familiar colours (gold and copper warm, silver and aluminium near white, chromium
// a grey darker than both).
TEST(MaterialMapping, PresetsAreMeasuredMetals) {
  const auto f0 = [](const char* preset) {
    MaterialDesc d = desc(MaterialType::kAnisotropicMetal, 0.3);
    d.preset = preset;
    const Material m = make_material(d);
    EXPECT_TRUE(m.complex_fresnel) << preset;
    EXPECT_EQ(m.albedo, vec3(1.0f));
    return m.albedo * fresnel_conductor(1.0f, m.eta, m.k);
  };
  const vec3 gold = f0("gold"), copper = f0("copper"), silver = f0("silver");
  const vec3 aluminium = f0("aluminium"), chromium = f0("chromium");
  EXPECT_EQ(f0("aluminum"), aluminium);
  EXPECT_GT(gold.x, 0.9f);
  EXPECT_LT(gold.z, 0.45f);
  EXPECT_GT(copper.x, copper.y);
  EXPECT_GT(copper.y, copper.z);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(silver[c], 0.85f);
    EXPECT_GT(aluminium[c], 0.85f);
    EXPECT_GT(chromium[c], 0.5f);
    EXPECT_LT(chromium[c], 0.75f);
  }
}

TEST(MaterialMapping, ExplicitIndexAndRoughGlass) {
  MaterialDesc d = desc(MaterialType::kMetal, 0.1);
  d.eta = glm::dvec3(0.18, 0.42, 1.37);
  d.k = glm::dvec3(3.42, 2.35, 1.77);
  const Material m = make_material(d);
  EXPECT_TRUE(m.complex_fresnel);
  EXPECT_EQ(m.eta, vec3(0.18f, 0.42f, 1.37f));
  const Material glass = make_material(desc(MaterialType::kGlass, 0.5));
  EXPECT_EQ(glass.kind, BsdfKind::kDielectric);
  EXPECT_FLOAT_EQ(glass.alpha_x, 0.25f);
  EXPECT_EQ(glass.albedo, vec3(1.0f));
  EXPECT_FALSE(glass.absorbs());
  MaterialDesc tinted = desc(MaterialType::kGlass, 0.0);
  tinted.transmittance = glm::dvec3(0.5, 1.0, 0.25);
  tinted.transmittance_distance = 2.0;
  const Material absorbing = make_material(tinted);
  EXPECT_TRUE(absorbing.absorbs());
  EXPECT_NEAR(absorbing.absorption.x, std::log(2.0) / 2.0, 1e-6);
  EXPECT_EQ(absorbing.absorption.y, 0.0f);
  EXPECT_NEAR(absorbing.absorption.z, std::log(4.0) / 2.0, 1e-6);
}

}  // namespace
}  // namespace tessera
