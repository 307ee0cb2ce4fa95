#pragma once
// Lights that are not shapes: point and spot lights, directional lights (a sun, a delta
// direction or a cone of directions of some angular radius) and the environment. They sit
// in the same light list as emissive shapes (LightSource, tagged PrimitiveType::kAnalyticLight
// with their index into SceneView::analytic_lights), so pick_light chooses them by power
// and sample_light samples them. Point, spot and zero-radius directional lights are deltas:
// no ray can hit them, so light sampling alone finds them (LightSource::visible false). A
// sun with an angular radius and the environment are found by escaping rays too, and the
// path tracer's miss program weighs those against light sampling (MIS).
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

enum class AnalyticLightKind : std::uint32_t { kPoint = 0, kSpot, kDistant, kEnvironment };

struct AnalyticLight {
  AnalyticLightKind kind = AnalyticLightKind::kPoint;
  vec3 position{0.0f};  // point, spot
  // Spot: the unit axis it shines along. Distant: unit, from the scene towards the light.
  vec3 direction{0.0f, 0.0f, 1.0f};
  // Point, spot: radiant intensity (W/sr, per channel). Distant: irradiance on a surface
  // facing it. Environment: unused (SceneView::environment holds it).
  vec3 emission{0.0f};
  // Spot: the cosines of the cone's edge (falloff reaches 0) and of where the falloff
  // starts (full intensity inside).
  float cos_outer = -1.0f, cos_inner = -1.0f;
  // Distant: 1 - cos of the angular radius; 0 for a delta direction.
  float one_minus_cos_radius = 0.0f;
};

// A spot light's falloff at cos_theta from its axis: 1 inside the inner cone, 0 outside
// the outer one, and a smoothstep of cos_theta between (pbrt-v4's spot falloff).
TESSERA_HD TESSERA_INLINE float spot_falloff(float cos_theta, float cos_outer, float cos_inner) {
  if (cos_theta >= cos_inner) return 1.0f;
  if (cos_theta <= cos_outer) return 0.0f;
  const float t = (cos_theta - cos_outer) / (cos_inner - cos_outer);
  return t * t * (3.0f - 2.0f * t);
}

// Whether the light is a cone of directions from infinity that escaping rays can hit.
TESSERA_HD TESSERA_INLINE bool distant_with_extent(const AnalyticLight& light) {
  return light.kind == AnalyticLightKind::kDistant && light.one_minus_cos_radius > 0.0f;
}

// Whether unit `direction` lies in a distant light's cone. The bound has 1e-4 of slack:
// 1 - cos of a quarter-degree cone is ~1e-5, where float rounding of the dot product alone
// is ~6e-8, and a sample drawn on the cone's edge must count as inside it.
TESSERA_HD TESSERA_INLINE bool in_distant_cone(const AnalyticLight& light, const vec3& direction) {
  return 1.0f - glm::dot(direction, light.direction) <= light.one_minus_cos_radius * 1.0001f;
}

// A distant light's radiance within its cone: irradiance E over the cosine-weighted solid
// angle of the cone, pi sin^2(radius) = pi (1 - cos)(1 + cos).
TESSERA_HD TESSERA_INLINE vec3 distant_radiance(const AnalyticLight& light) {
  const float omc = light.one_minus_cos_radius;
  return light.emission / (kPi * omc * (2.0f - omc));
}

}  // namespace tessera
