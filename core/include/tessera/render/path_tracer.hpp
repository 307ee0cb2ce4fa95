#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/math/offset_ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/pipeline/pipeline.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/render/tile.hpp"

namespace tessera {

// The path tracer as pipeline programs: ray generation shoots camera rays and writes the
// film, the hit program does next-event estimation with any-hit shadow rays and picks the
// continuation ray, the miss program adds the background.

struct PathPayload {
  vec3 radiance{0.0f};
  vec3 throughput{1.0f};
  SampleStream samples{0, 0, 0, 0};
  std::uint32_t depth = 0;
  std::uint32_t rays = 0;      // every ray traced for this sample, for rays/s
  bool count_emission = true;  // camera rays and specular bounces see emitters directly
  bool has_next_ray = false;
  Ray next_ray;
};

struct PathRayGeneration {
  using Payload = PathPayload;
  Camera camera;
  std::uint64_t seed;
  TileRect tile;
  float sample_weight;       // 1 / samples per pixel
  float* film;               // tile.width * tile.height RGBA, accumulated
  std::uint64_t* ray_count;  // per tile, so one writer

  TESSERA_HD Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                          Payload& payload) const {
    payload.samples = SampleStream(seed, x, y, sample);
    const float jx = payload.samples.next();
    const float jy = payload.samples.next();
    payload.rays = 1;
    return camera.generate(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
  }

  TESSERA_HD void on_result(std::uint32_t x, std::uint32_t y, std::uint32_t,
                            const Payload& payload) const {
    *ray_count += payload.rays;
    const vec3 l = payload.radiance;
    // A NaN or infinite sample would poison the pixel forever; drop it instead.
    if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) return;
    float* pixel = film + 4 * ((static_cast<std::size_t>(y) - tile.y) * tile.width + (x - tile.x));
    pixel[0] += l.x * sample_weight;
    pixel[1] += l.y * sample_weight;
    pixel[2] += l.z * sample_weight;
  }
};

struct BackgroundMiss {
  vec3 background;

  TESSERA_HD void on_miss(const Ray&, PathPayload& payload) const {
    payload.radiance += payload.throughput * background;
  }
};

template <unsigned kShapes>
struct PathHit {
  SceneView scene;
  std::uint32_t max_depth;

  template <typename T>
  TESSERA_HD void on_hit(const Ray& ray, const HitRecord& hit, PathPayload& payload,
                         const T& tracer) const {
    const SurfaceInteraction si = surface_at<kShapes>(scene, ray, hit);
    const Material& material = scene.materials[si.material];
    if (material.emissive() && payload.count_emission)
      payload.radiance += payload.throughput * material.emission;
    if (material.kind == BsdfKind::kEmitter) return;
    if (payload.depth + 1 >= max_depth) return;

    const vec3 n = si.geometric_normal;  // faces the incoming ray
    const vec3 wo = ray.direction;
    vec3 direction(0.0f);
    SampleStream& rng = payload.samples;
    bool diffuse = false;

    switch (material.kind) {
      case BsdfKind::kDiffuse:
        diffuse = true;
        break;
      case BsdfKind::kCoated: {
        const float f = schlick_reflectance(-glm::dot(wo, n), 1.0f / material.ior);
        if (rng.next() < f) {
          direction = fuzzy_reflect(wo, n, material.roughness, rng.next(), rng.next(), rng.next());
        } else {
          diffuse = true;
        }
        break;
      }
      case BsdfKind::kConductor:
        direction = fuzzy_reflect(wo, n, material.roughness, rng.next(), rng.next(), rng.next());
        payload.throughput *= material.albedo;
        break;
      case BsdfKind::kDielectric: {
        const float eta = si.front_face ? 1.0f / material.ior : material.ior;
        const float cos_i = -glm::dot(wo, n);
        vec3 refracted;
        const bool can_refract = refract(wo, n, eta, refracted);
        if (!can_refract || rng.next() < schlick_reflectance(cos_i, eta)) {
          direction = reflect(wo, n);
        } else {
          direction = refracted;
        }
        payload.throughput *= material.albedo;
        break;
      }
      case BsdfKind::kThinDielectric: {
        // Two interfaces close together: reflectance R' = 2R / (1 + R), transmission straight on.
        const float r = schlick_reflectance(-glm::dot(wo, n), 1.0f / material.ior);
        direction = rng.next() < 2.0f * r / (1.0f + r) ? reflect(wo, n) : wo;
        break;
      }
      case BsdfKind::kEmitter:
        return;
    }

    if (diffuse) {
      payload.throughput *= material.albedo;
      sample_direct_light(si, payload, tracer);
      const Frame frame = Frame::from_normal(n);
      direction = frame.to_world(sample_cosine_hemisphere(rng.next(), rng.next()));
      payload.count_emission = false;
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
  // One light chosen uniformly, one point uniformly on its area, one shadow ray.
  template <typename T>
  TESSERA_HD void sample_direct_light(const SurfaceInteraction& si, PathPayload& payload,
                                      const T& tracer) const {
    if (scene.light_count == 0) return;
    SampleStream& rng = payload.samples;
    const float pick = rng.next() * static_cast<float>(scene.light_count);
    const std::uint32_t light_index =
        glm::min(static_cast<std::uint32_t>(pick), scene.light_count - 1);
    const LightSource& light = scene.lights[light_index];
    const float u1 = rng.next();
    const float u2 = rng.next();
    vec3 point, light_normal;
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
    }
    const vec3 n = si.geometric_normal;
    const vec3 origin = offset_ray_origin(si.position, n);
    const vec3 to_light = point - origin;
    const float distance2 = glm::dot(to_light, to_light);
    if (!(distance2 > 0.0f)) return;
    const float distance = std::sqrt(distance2);
    const vec3 wi = to_light / distance;
    const float cos_surface = glm::dot(wi, n);
    const float cos_light = std::fabs(glm::dot(wi, light_normal));  // emitters are two-sided
    if (cos_surface <= 0.0f || cos_light <= 0.0f) return;
    ++payload.rays;
    // Stop just short of the light so the shadow ray cannot hit the light itself.
    if (tracer.occluded(Ray{origin, wi, 0.0f, distance * (1.0f - 1e-4f)})) return;
    const float pdf_area = 1.0f / (light.area * static_cast<float>(scene.light_count));
    const vec3 emission = scene.materials[material].emission;
    payload.radiance +=
        payload.throughput * emission * (kInvPi * cos_surface * cos_light / (distance2 * pdf_area));
  }
};

template <unsigned kShapes>
struct PathTracerConfig {
  using RayGeneration = PathRayGeneration;
  using Intersection = SceneIntersection<kShapes>;
  using Hit = PathHit<kShapes>;
  using Miss = BackgroundMiss;
};

}  // namespace tessera
