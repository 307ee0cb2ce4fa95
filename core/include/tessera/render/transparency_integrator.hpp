#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/render/path_tracer.hpp"

namespace tessera {

inline constexpr int kTransparencyMaxHits = 16;

// Multi-hit transparency: every surface along the camera ray (up to kTransparencyMaxHits,
// sorted by t) is composited front to back with its material's opacity, over the
// background. Surfaces are lit by a headlight so shape reads without lights.
template <unsigned kShapes>
struct TransparencyHit {
  SceneView scene;
  bool transparent_background = false;  // composite over nothing: alpha is the coverage

  template <typename T>
  TESSERA_HD void on_hits(const Ray& ray, const HitRecord* hits, int count,
                          PathPayload<false>& payload, const T&) const {
    vec3 color(0.0f);
    float alpha = 0.0f;
    const vec3 view = glm::normalize(ray.direction);
    for (int i = 0; i < count && alpha < 0.999f; ++i) {
      const SurfaceInteraction si = surface_at<kShapes>(scene, ray, hits[i]);
      const Material& m = scene.materials[si.material];
      const vec3 albedo =
          albedo_at(scene, m, hits[i].primitive, si,
                    scene.camera.footprint_at(hits[i].t * glm::length(ray.direction)));
      const vec3 surface =
          m.unlit()      ? m.unlit_color(albedo, si.shading_normal)
          : m.emissive() ? m.emission
                         : albedo * (0.25f + 0.75f * std::fabs(glm::dot(view, si.shading_normal)));
      const float weight = (1.0f - alpha) * m.opacity;
      color += weight * surface;
      alpha += weight;
    }
    payload.coverage = alpha;
    payload.radiance = transparent_background ? color : color + (1.0f - alpha) * scene.background;
  }
};

template <unsigned kShapes>
struct TransparencyConfig {
  using RayGeneration = PathRayGeneration<false>;
  using Intersection = SceneIntersection<kShapes>;
  using Hit = TransparencyHit<kShapes>;
  using Miss = BackgroundMiss;
  static constexpr int kMaxHits = kTransparencyMaxHits;
};

}  // namespace tessera
