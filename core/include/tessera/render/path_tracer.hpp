#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "tessera/math/offset_ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/pipeline/pipeline.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/film.hpp"
#include "tessera/render/pipeline_features.hpp"
#include "tessera/render/scene_data.hpp"

namespace tessera {

// The path tracer as pipeline programs: ray generation shoots camera rays and writes the
// film, the hit program does next-event estimation with any-hit shadow rays and picks the
// continuation ray, the miss program adds the background. PipelineFeatures decide what is
// compiled in.

struct NoAovs {};

template <bool kAovs>
struct PathPayload {
  vec3 radiance{0.0f};
  vec3 throughput{1.0f};
  SampleStream samples{0, 0, 0, 0};
  std::uint32_t depth = 0;
  std::uint32_t rays = 0;      // every ray traced for this sample, for rays/s
  bool count_emission = true;  // camera rays and specular bounces see emitters directly
  bool has_next_ray = false;
  Ray next_ray;
  [[no_unique_address]] std::conditional_t<kAovs, FirstHitAovs, NoAovs> aov;
};

// Camera rays through jittered pixel positions; averages samples into the film.
template <bool kAovs>
struct PathRayGeneration {
  using Payload = PathPayload<kAovs>;
  Camera camera;
  std::uint64_t seed;
  TileRect tile;
  float sample_weight;  // 1 / samples per pixel
  FilmPlanes film;
  std::uint64_t* ray_count;  // per tile, so one writer

  TESSERA_HD void init_payload(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                               Payload& payload) const {
    payload.samples = SampleStream(seed, x, y, sample);
  }

  TESSERA_HD Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t, Payload& payload) const {
    const float jx = payload.samples.next();
    const float jy = payload.samples.next();
    payload.rays = 1;
    return camera.generate(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
  }

  TESSERA_HD void on_result(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                            const Payload& payload) const {
    *ray_count += payload.rays;
    const std::size_t at = FilmPlanes::offset(tile, x, y);
    if constexpr (kAovs) {
      if (film.albedo) FilmPlanes::add(film.albedo, at, payload.aov.albedo, sample_weight);
      if (film.normal) FilmPlanes::add(film.normal, at, payload.aov.normal, sample_weight);
      if (film.depth) FilmPlanes::add(film.depth, at, vec3(payload.aov.depth), sample_weight);
      if (film.primitive_id && sample == 0)
        FilmPlanes::add(film.primitive_id, at, vec3(static_cast<float>(payload.aov.primitive + 1u)),
                        1.0f);
    }
    const vec3 l = payload.radiance;
    // A NaN or infinite sample would poison the pixel forever; drop it instead.
    if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) return;
    FilmPlanes::add(film.beauty, at, l, sample_weight);
  }
};

struct BackgroundMiss {
  vec3 background;

  template <typename Payload>
  TESSERA_HD void on_miss(const Ray&, Payload& payload) const {
    payload.radiance += payload.throughput * background;
  }
};

// One light chosen uniformly, one point uniformly on its area, one any-hit shadow ray.
// Returns the radiance arriving at `si` (times cos / pi: a Lambertian response for unit
// albedo), zero when occluded.
template <typename T>
TESSERA_HD vec3 sample_direct_light(const SceneView& scene, const SurfaceInteraction& si,
                                    SampleStream& rng, const T& tracer, std::uint32_t& rays) {
  if (scene.light_count == 0) return vec3(0.0f);
  const float pick = rng.next() * static_cast<float>(scene.light_count);
  const std::uint32_t light_index =
      glm::min(static_cast<std::uint32_t>(pick), scene.light_count - 1);
  const LightSource& light = scene.lights[light_index];
  const float u1 = rng.next();
  const float u2 = rng.next();
  vec3 point(0.0f), light_normal(0.0f, 0.0f, 1.0f);
  std::uint32_t material = 0;
  const std::uint32_t index = primitive_index(light.primitive);
  switch (primitive_type(light.primitive)) {
    case PrimitiveType::kSphere: {
      const Sphere& s = scene.spheres[index];
      light_normal = sample_uniform_sphere(u1, u2);
      point = s.center + s.radius * light_normal;
      material = s.material;
      break;
    }
    case PrimitiveType::kQuad: {
      const Quad& q = scene.quads[index];
      point = q.corner + u1 * q.u + u2 * q.v;
      light_normal = q.normal;
      material = q.material;
      break;
    }
    case PrimitiveType::kTriangle: {
      const Triangle& t = scene.triangles[index];
      const vec2 b = sample_uniform_triangle(u1, u2);
      point = b.x * t.p0 + b.y * t.p1 + (1.0f - b.x - b.y) * t.p2;
      light_normal = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
      material = t.material;
      break;
    }
    case PrimitiveType::kDisk: {
      // Uniform in area over the annulus: radius by the inverse of its area CDF.
      const Disk& d = scene.disks[index];
      const float r2 = d.inner_radius * d.inner_radius;
      const float rho = std::sqrt(r2 + u1 * (d.radius * d.radius - r2));
      const float phi = 2.0f * kPi * u2;
      const Frame frame = Frame::from_normal(d.normal);
      point = d.center + frame.to_world(vec3(rho * std::cos(phi), rho * std::sin(phi), 0.0f));
      light_normal = d.normal;
      material = d.material;
      break;
    }
    default:  // no sampler (has_light_sampler): never in the light list
      return vec3(0.0f);
  }
  const vec3 n = si.geometric_normal;
  const vec3 origin = offset_ray_origin(si.position, n);
  const vec3 to_light = point - origin;
  const float distance2 = glm::dot(to_light, to_light);
  if (!(distance2 > 0.0f)) return vec3(0.0f);
  const float distance = std::sqrt(distance2);
  const vec3 wi = to_light / distance;
  const float cos_surface = glm::dot(wi, n);
  const float cos_light = std::fabs(glm::dot(wi, light_normal));  // emitters are two-sided
  if (cos_surface <= 0.0f || cos_light <= 0.0f) return vec3(0.0f);
  ++rays;
  // Stop just short of the light so the shadow ray cannot hit the light itself.
  if (tracer.occluded(Ray{origin, wi, 0.0f, distance * (1.0f - 1e-4f)})) return vec3(0.0f);
  const float pdf_area = 1.0f / (light.area * static_cast<float>(scene.light_count));
  return scene.materials[material].emission *
         (kInvPi * cos_surface * cos_light / (distance2 * pdf_area));
}

template <PipelineFeatures kFeatures>
struct PathHit {
  SceneView scene;
  std::uint32_t max_depth;

  template <typename T>
  TESSERA_HD void on_hit(const Ray& ray, const HitRecord& hit, PathPayload<kFeatures.aovs>& payload,
                         const T& tracer) const {
    const SurfaceInteraction si = surface_at<kFeatures.shapes>(scene, ray, hit);
    const Material& material = scene.materials[si.material];
    if constexpr (kFeatures.aovs) {
      if (payload.depth == 0) {
        payload.aov.albedo = material.albedo;
        payload.aov.normal = si.shading_normal;
        payload.aov.depth = hit.t * glm::length(ray.direction);
        payload.aov.primitive = hit.primitive;
      }
    }
    // Emitters without an area sampler are not in the light list, so next-event estimation
    // never reaches them: their emission is counted whenever a ray hits them instead.
    if (material.emissive() &&
        (payload.count_emission || !has_light_sampler(primitive_type(hit.primitive))))
      payload.radiance += payload.throughput * material.emission;
    if (material.kind == BsdfKind::kEmitter) return;
    if (payload.depth + 1 >= max_depth) return;

    const vec3 n = si.geometric_normal;  // faces the incoming ray
    const vec3 wo = ray.direction;
    vec3 direction(0.0f);
    SampleStream& rng = payload.samples;
    bool diffuse = true;
    if constexpr (kFeatures.specular)
      diffuse = scatter_specular(material, si, wo, rng, payload, direction);

    if (diffuse) {
      payload.throughput *= material.albedo;
      if constexpr (kFeatures.direct_lighting)
        payload.radiance +=
            payload.throughput * sample_direct_light(scene, si, rng, tracer, payload.rays);
      const Frame frame = Frame::from_normal(n);
      direction = frame.to_world(sample_cosine_hemisphere(rng.next(), rng.next()));
      // Next-event estimation already counted emitters seen from here; with no lights to
      // sample, a diffuse bounce must see them itself.
      payload.count_emission = !kFeatures.direct_lighting;
    } else {
      payload.count_emission = true;
    }
    if (direction == vec3(0.0f)) return;

    // Russian roulette keeps long paths unbiased without tracing every one to max depth.
    ++payload.depth;
    if (payload.depth >= 3) {
      const float survive = glm::clamp(max_component(payload.throughput), 0.05f, 1.0f);
      if (rng.next() >= survive) return;
      payload.throughput /= survive;
    }
    const vec3 side = glm::dot(direction, n) >= 0.0f ? n : -n;
    payload.next_ray = Ray{offset_ray_origin(si.position, side), direction, 0.0f, kInfinity};
    payload.has_next_ray = true;
    ++payload.rays;
  }

 private:
  // Handles the non-diffuse BSDFs; returns true when the surface should scatter diffusely.
  TESSERA_HD static bool scatter_specular(const Material& material, const SurfaceInteraction& si,
                                          const vec3& wo, SampleStream& rng,
                                          PathPayload<kFeatures.aovs>& payload, vec3& direction) {
    const vec3 n = si.geometric_normal;
    switch (material.kind) {
      case BsdfKind::kDiffuse:
      case BsdfKind::kEmitter:
        return true;
      case BsdfKind::kCoated: {
        const float f = schlick_reflectance(-glm::dot(wo, n), 1.0f / material.ior);
        if (rng.next() >= f) return true;
        direction = fuzzy_reflect(wo, n, material.roughness, rng.next(), rng.next(), rng.next());
        return false;
      }
      case BsdfKind::kConductor:
        direction = fuzzy_reflect(wo, n, material.roughness, rng.next(), rng.next(), rng.next());
        payload.throughput *= material.albedo;
        return false;
      case BsdfKind::kDielectric: {
        const float eta = si.front_face ? 1.0f / material.ior : material.ior;
        const float cos_i = -glm::dot(wo, n);
        vec3 refracted;
        const bool can_refract = refract(wo, n, eta, refracted);
        direction = (!can_refract || rng.next() < schlick_reflectance(cos_i, eta)) ? reflect(wo, n)
                                                                                   : refracted;
        payload.throughput *= material.albedo;
        return false;
      }
      case BsdfKind::kThinDielectric: {
        // Two interfaces close together: reflectance R' = 2R / (1 + R), transmission straight on.
        const float r = schlick_reflectance(-glm::dot(wo, n), 1.0f / material.ior);
        direction = rng.next() < 2.0f * r / (1.0f + r) ? reflect(wo, n) : wo;
        return false;
      }
    }
    return true;
  }
};

template <PipelineFeatures kFeatures>
struct PathTracerConfig {
  using RayGeneration = PathRayGeneration<kFeatures.aovs>;
  using Intersection = SceneIntersection<kFeatures.shapes>;
  using Hit = PathHit<kFeatures>;
  using Miss = BackgroundMiss;
};

}  // namespace tessera
