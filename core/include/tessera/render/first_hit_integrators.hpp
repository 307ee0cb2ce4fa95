#pragma once
#include <cstdint>

#include "tessera/render/path_tracer.hpp"

namespace tessera {

// Integrators that look only at the first surface a camera ray meets: normals, albedo and
// depth previews. One continuation-free pipeline; `kOutput` picks the value written.
enum class FirstHitOutput { kNormals, kAlbedo, kDepth };

struct FirstHitPayload {
  vec3 value{0.0f};
  float coverage = 1.0f;  // 0 when the camera ray missed
  SampleStream samples{0, 0, 0, 0};
  bool has_next_ray = false;
  Ray next_ray;
};

struct FirstHitRayGeneration {
  using Payload = FirstHitPayload;
  Camera camera;
  std::uint64_t seed;
  TileRect tile;
  float sample_weight;
  FilmPlanes film;
  std::uint64_t* ray_count;
  SamplerKind sampler = SamplerKind::kIndependent;

  TESSERA_HD Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                          Payload& payload) const {
    payload.samples = SampleStream(seed, x, y, sample, sampler);
    return camera.generate_sample(x, y, payload.samples);
  }
  TESSERA_HD void on_result(std::uint32_t x, std::uint32_t y, std::uint32_t,
                            const Payload& payload) const {
    ++*ray_count;
    const std::size_t at = FilmPlanes::offset(tile, x, y);
    FilmPlanes::add(film.beauty, at, payload.value, sample_weight);
    film.beauty[at + 3] += payload.coverage * sample_weight;
  }
};

template <unsigned kShapes, FirstHitOutput kOutput>
struct FirstHitShade {
  SceneView scene;

  template <typename T>
  TESSERA_HD void on_hit(const Ray& ray, const HitRecord& hit, FirstHitPayload& payload,
                         const T&) const {
    if constexpr (kOutput == FirstHitOutput::kDepth) {
      payload.value = vec3(hit.t * glm::length(ray.direction));
    } else {
      const SurfaceInteraction si = surface_at<kShapes>(scene, ray, hit);
      if constexpr (kOutput == FirstHitOutput::kNormals) {
        payload.value = 0.5f * si.shading_normal + vec3(0.5f);
      } else {
        payload.value = albedo_at(scene, scene.materials[si.material], hit.primitive, si,
                                  scene.camera.footprint_at(hit.t * glm::length(ray.direction)));
      }
    }
  }
};

struct BlackMiss {
  TESSERA_HD void on_miss(const Ray&, FirstHitPayload& payload) const {
    payload.value = vec3(0.0f);
    payload.coverage = 0.0f;
  }
};

template <unsigned kShapes, FirstHitOutput kOutput>
struct FirstHitConfig {
  using RayGeneration = FirstHitRayGeneration;
  using Intersection = SceneIntersection<kShapes>;
  using Hit = FirstHitShade<kShapes, kOutput>;
  using Miss = BlackMiss;
};

}  // namespace tessera
