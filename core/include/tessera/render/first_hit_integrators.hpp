#pragma once
#include <cstdint>

#include "tessera/render/path_tracer.hpp"

namespace tessera {

// Integrators that look only at the first surface a camera ray meets: normals, albedo,
// depth and Phong previews. One continuation-free pipeline; `kOutput` picks the value written.
enum class FirstHitOutput { kNormals, kAlbedo, kDepth, kPhong };

// The Phong preview: Blinn-Phong under a light at the eye, as CAD viewers shade, so shape
// reads at one sample per pixel with no noise and no shadows. Diffuse albedo times an
// ambient floor plus the cosine to the eye; conductors, coats and glass add a highlight whose
// exponent is the Blinn-Phong match of their GGX alpha (2 / alpha^2 - 2, Walter et al. 2007),
// tinted by the albedo on conductors and 4% white otherwise. Emitters show their emission,
// unlit materials their colour.
TESSERA_HD inline vec3 phong_preview(const Material& m, const vec3& albedo, const vec3& normal,
                                     const vec3& to_eye) {
  if (m.unlit()) return m.unlit_color(albedo, normal);
  if (m.kind == BsdfKind::kEmitter) return m.emission;
  constexpr float kAmbient = 0.15f;
  const float facing = glm::max(glm::dot(normal, to_eye), 0.0f);
  const bool metal = m.kind == BsdfKind::kConductor;
  vec3 colour = metal ? vec3(0.0f) : albedo * (kAmbient + (1.0f - kAmbient) * facing);
  if (m.kind != BsdfKind::kDiffuse) {
    const float alpha = glm::clamp(glm::max(m.alpha_x, m.alpha_y), 0.05f, 1.0f);
    const float exponent = 2.0f / (alpha * alpha) - 2.0f;
    // Conductors have no diffuse part: an ambient share of their colour keeps them visible
    // away from the highlight.
    const vec3 tint = metal ? albedo : vec3(0.04f);
    colour += tint * (metal ? kAmbient + (1.0f - kAmbient) * std::pow(facing, exponent)
                            : std::pow(facing, exponent));
  }
  return colour + m.emission;
}

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
  SobolSeedMemo* sobol_memo = nullptr;  // as PathRayGeneration's

  TESSERA_HD Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                          Payload& payload) const {
    payload.samples.restart(seed, x, y, sample, sampler, sobol_memo);
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
      SurfaceInteraction si = surface_at<kShapes>(scene, ray, hit);
      apply_golf_dimples(scene, scene.materials[si.material], hit.primitive, ray, si);
      if constexpr (kOutput == FirstHitOutput::kNormals) {
        payload.value = 0.5f * si.shading_normal + vec3(0.5f);
      } else {
        const float footprint = scene.camera.footprint_at(hit.t * glm::length(ray.direction));
        MaterialScratch textured;
        const Material& material = material_at(scene, scene.materials[si.material], hit.primitive,
                                               si, footprint, textured);
        const vec3 albedo = albedo_at(scene, material, hit.primitive, si, footprint);
        if constexpr (kOutput == FirstHitOutput::kPhong)
          payload.value =
              phong_preview(material, albedo, si.shading_normal, -glm::normalize(ray.direction));
        else
          payload.value = albedo;
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
