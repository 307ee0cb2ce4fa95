#include "analytic_lights.hpp"

#include <cmath>

namespace tessera {

namespace {

constexpr double kDegrees = 3.14159265358979323846 / 180.0;

AnalyticLight bounded_light(const LightDesc& d) {
  AnalyticLight light;
  light.kind = d.type == "spot" ? AnalyticLightKind::kSpot : AnalyticLightKind::kPoint;
  light.position = vec3(d.position);
  light.emission = vec3(d.color * d.intensity);
  if (light.kind == AnalyticLightKind::kSpot) {
    light.direction = vec3(glm::normalize(d.direction));
    const double outer = d.cone_angle_degrees * kDegrees;
    const double inner = std::max(0.0, d.cone_angle_degrees - d.cone_falloff_degrees) * kDegrees;
    light.cos_outer = static_cast<float>(std::cos(outer));
    light.cos_inner = static_cast<float>(std::cos(inner));
  }
  return light;
}

AnalyticLight distant_light(const LightDesc& d) {
  AnalyticLight light;
  light.kind = AnalyticLightKind::kDistant;
  // Stored towards the light: the way shadow rays and light samples go.
  light.direction = vec3(-glm::normalize(d.direction));
  light.emission = vec3(d.color * d.irradiance);
  // 1 - cos in the form that keeps its precision for the sun's quarter degree.
  const double half = 0.5 * d.angular_radius_degrees * kDegrees;
  light.one_minus_cos_radius = static_cast<float>(2.0 * std::sin(half) * std::sin(half));
  return light;
}

bool is_distant(const LightDesc& d) {
  return d.type == "directional" || d.type == "sun";
}

}  // namespace

AnalyticLightSet make_analytic_lights(const SceneDescription& description) {
  AnalyticLightSet set;
  for (const LightDesc& d : description.lights)
    if (!is_distant(d)) set.lights.push_back(bounded_light(d));
  set.first_infinite = static_cast<std::uint32_t>(set.lights.size());
  for (const LightDesc& d : description.lights)
    if (is_distant(d)) set.lights.push_back(distant_light(d));

  if (description.environment) {
    const EnvironmentDesc& e = *description.environment;
    set.environment.kind =
        e.type == "gradient" ? EnvironmentKind::kGradient : EnvironmentKind::kConstant;
    set.environment.scale = set.environment.kind == EnvironmentKind::kGradient
                                ? vec3(static_cast<float>(e.intensity))
                                : vec3(e.color * e.intensity);
    if (e.type == "image") build_environment_map(e, set.environment, set.environment_tables);
  } else {
    set.environment.scale = vec3(description.background.color * description.background.intensity);
  }
  if (!set.environment.black()) {
    AnalyticLight env;
    env.kind = AnalyticLightKind::kEnvironment;
    set.lights.push_back(env);
  }
  return set;
}

}  // namespace tessera
