#pragma once
#include <cstdint>

#include "tessera/render/path_tracer.hpp"

namespace tessera {

// Direct lighting only: the first surface seen, lit by one sampled light through an
// any-hit shadow ray, shaded as Lambertian with its albedo. A fast preview of lighting and
// shadows; reuses the path tracer's payload (no AOVs) and ray generation.
template <unsigned kShapes>
struct ShadowHit {
  SceneView scene;

  template <typename T>
  TESSERA_HD void on_hit(const Ray& ray, const HitRecord& hit, PathPayload<false>& payload,
                         const T& tracer) const {
    const SurfaceInteraction si = surface_at<kShapes>(scene, ray, hit);
    const Material& material = scene.materials[si.material];
    payload.radiance += material.emission;
    if (material.kind == BsdfKind::kEmitter) return;
    const vec3 albedo = albedo_at(scene, material, hit.primitive, si,
                                  scene.camera.footprint_at(hit.t * glm::length(ray.direction)));
    if (material.unlit()) {
      payload.radiance += material.unlit_color(albedo, si.shading_normal);
      return;
    }
    payload.radiance +=
        albedo * sample_direct_light(scene, si, payload.samples, tracer, payload.rays);
  }
};

template <unsigned kShapes>
struct ShadowConfig {
  using RayGeneration = PathRayGeneration<false>;
  using Intersection = SceneIntersection<kShapes>;
  using Hit = ShadowHit<kShapes>;
  using Miss = BackgroundMiss;
};

}  // namespace tessera
