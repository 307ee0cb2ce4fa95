#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "tessera/math/offset_ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/pipeline/pipeline.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/film.hpp"
#include "tessera/render/light_sampling.hpp"
#include "tessera/render/pipeline_features.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/render/surface_textures.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// The path tracer as pipeline programs: ray generation shoots camera rays and writes the
// film, the hit program does next-event estimation with any-hit shadow rays, weighted
// against BSDF sampling by multiple importance sampling, and samples the BSDF for the
// continuation ray; the miss program adds the environment (PathMiss). PipelineFeatures decide what
// is compiled in.

struct NoAovs {};

template <bool kAovs>
struct PathPayload {
  vec3 radiance{0.0f};
  vec3 throughput{1.0f};
  SampleStream samples{0, 0, 0, 0};
  // Vertices so far, each with its own block of sample dimensions; `depth - film_crossings`
  // of them scattered (what max_depth, roulette and clamping count).
  std::uint32_t depth = 0;
  std::uint32_t film_crossings = 0;  // straight passes through thin films (see PathHit)
  TESSERA_HD std::uint32_t bounces() const { return depth - film_crossings; }
  std::uint32_t rays = 0;      // every ray traced for this sample, for rays/s
  bool count_emission = true;  // camera rays and specular bounces see emitters directly
  float previous_pdf = 0.0f;   // of the BSDF sample that led here, for MIS at emitters
  vec3 previous_position{0.0f};
  vec3 previous_normal{0.0f};  // geometric, on the side the path arrived from
  bool has_next_ray = false;
  Ray next_ray;
  // The sample's share of the pixel's alpha: 1 when the camera ray hit a surface, 0 when it
  // missed (BackgroundMiss), the composited opacity for the transparency preview.
  float coverage = 1.0f;
  // The ray cone (Amanatides 1984; Akenine-Moller et al. 2019) that picks texture mip
  // levels: its width at the path's last vertex and how fast it widens per unit distance.
  float cone_width = 0.0f;
  float cone_spread = 0.0f;
  [[no_unique_address]] std::conditional_t<kAovs, FirstHitAovs, NoAovs> aov;
};

// Camera rays through pixel positions drawn from the pixel filter (Camera::generate_sample);
// averages samples into the film.
template <bool kAovs>
struct PathRayGeneration {
  using Payload = PathPayload<kAovs>;
  // The scene's (620 bytes), the caller's, which outlives the program object. A copy would put
  // these bytes on every GPU thread's stack (local memory): by reference the kernel reads its
  // __grid_constant__ parameter through the constant cache.
  const Camera& camera;
  std::uint64_t seed;
  TileRect tile;
  float sample_weight;  // 1 / samples per pixel
  FilmPlanes film;
  std::uint64_t* ray_count;  // per tile, so one writer
  SamplerKind sampler = SamplerKind::kIndependent;
  // The tile loop's memo of each pixel's Sobol seeds (SobolSeedMemo); null: none (the GPU).
  SobolSeedMemo* sobol_memo = nullptr;

  TESSERA_HD void init_payload(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                               Payload& payload) const {
    payload.samples.restart(seed, x, y, sample, sampler, sobol_memo);
  }

  TESSERA_HD Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t, Payload& payload) const {
    payload.rays = 1;
    payload.cone_width = camera.footprint_at(0.0f);
    payload.cone_spread = camera.pixel_spread();
    return camera.generate_sample(x, y, payload.samples);
  }

  TESSERA_HD void on_result(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                            const Payload& payload) const {
    *ray_count += payload.rays;
    const std::size_t at = FilmPlanes::offset(tile, x, y);
    if constexpr (kAovs) {
      if (film.albedo) FilmPlanes::add(film.albedo, at, payload.aov.albedo, sample_weight);
      if (film.normal) FilmPlanes::add(film.normal, at, payload.aov.normal, sample_weight);
      if (film.depth) FilmPlanes::keep_nearest(film.depth, at, payload.aov.depth);
      if (film.primitive_id && sample == 0)
        film.primitive_id[at] = id_as_float(payload.aov.primitive + 1u);
    }
    film.beauty[at + 3] += payload.coverage * sample_weight;
    const vec3 l = payload.radiance;
    // A NaN or infinite sample would poison the pixel forever; drop it instead.
    if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) return;
    FilmPlanes::add(film.beauty, at, l, sample_weight);
  }
};

// Cycles' indirect light clamp: light that reaches the camera after two or more bounces
// (its path's vertex count past the first surface, `depth`, is 2 or more for emission and
// misses, 1 or more for next-event estimation at a later vertex) is scaled down, hue kept,
// until its largest component is at most `limit`. Direct light (emitters and background
// seen by the camera or lighting the first surface) is never clamped. 0 = off.
TESSERA_HD TESSERA_INLINE vec3 clamp_indirect(const vec3& contribution, float limit,
                                              bool indirect) {
  if (!indirect || !(limit > 0.0f)) return contribution;
  const float largest = max_component(contribution);
  return largest > limit ? contribution * (limit / largest) : contribution;
}

// A camera ray that misses leaves the sample uncovered (alpha 0); with
// `transparent_background` it adds no background either, so the pixel composites over
// another plate (RGB premultiplied by alpha). Rays after a bounce always see the
// background: it still lights the scene.
struct BackgroundMiss {
  vec3 background;
  bool transparent_background = false;
  float clamp = 0.0f;  // RenderSettings::clamp

  template <typename Payload>
  TESSERA_HD void on_miss(const Ray&, Payload& payload) const {
    if (payload.depth == 0) {
      payload.coverage = 0.0f;
      if (transparent_background) return;
    }
    payload.radiance += clamp_indirect(payload.throughput * background, clamp, payload.depth >= 2);
  }
};

// Random dimensions: the camera takes the first kCameraDimensions (the position in the
// pixel; a thin lens draws from kLensDimension, far past these), each bounce a block
// of kBounceDimensions, so a dimension means the same decision in every sample of a pixel
// and the low-discrepancy sampler stratifies it. A block is three 2D pairs: the BSDF
// direction, the point on the light, and (lobe, light pick). Each pair is drawn only when
// the vertex uses it (a Sobol pair costs two scrambles and a shuffle); a diffuse vertex
// picks its light with the light point's first coordinate instead
// (BounceSamples::pick_with_light_point). Russian roulette takes white noise, which
// stratifying would not improve.
// The point on the light is joined to the pair that led to the vertex (SampleStream::
// next_2d_joined): the camera's position in the pixel at the first vertex, the previous
// vertex's BSDF direction after that. Each such 4D set is stratified as a whole, so where
// a path goes and which part of a light it then sees are spread evenly together: an area
// light's penumbra across a pixel, and the light a diffuse bounce finds. Measured on
// mesh_250k (256 spp, seeds 1-3): relMSE 0.00040 -> 0.00032 (-21%); joined to the previous
// direction only, -15%.
inline constexpr std::uint32_t kCameraDimensions = 2;
inline constexpr std::uint32_t kBounceDimensions = 6;
enum class BouncePair : std::uint32_t { kBsdfDirection = 0, kLightPoint = 1, kLobeAndPick = 2 };
struct BounceSamples {
  float light_pick = 0.0f, lobe = 0.0f;
  float light_u1 = 0.0f, light_u2 = 0.0f;
  float bsdf_u1 = 0.0f, bsdf_u2 = 0.0f;
  // The light is picked with light_u1, which the picked light's sampler then takes as what
  // is left of it (LightPick::reused_u), instead of with light_pick: a diffuse vertex, which
  // needs no lobe, then skips the (lobe, light pick) pair.
  bool pick_with_light_point = false;

  TESSERA_HD static void draw(SampleStream& rng, std::uint32_t depth, BouncePair pair, float& a,
                              float& b) {
    rng.set_dimension(kCameraDimensions + depth * kBounceDimensions +
                      2 * static_cast<std::uint32_t>(pair));
    if (pair == BouncePair::kBsdfDirection) return rng.next_2d_kept(a, b);
    if (pair != BouncePair::kLightPoint) return rng.next_2d(a, b);
    rng.next_2d_joined(depth == 0 ? 0u
                                  : kCameraDimensions + (depth - 1) * kBounceDimensions +
                                        2 * static_cast<std::uint32_t>(BouncePair::kBsdfDirection),
                       a, b);
  }
  TESSERA_HD static float roulette(const SampleStream& rng, std::uint32_t depth) {
    return rng.white(kCameraDimensions + depth * kBounceDimensions + 6);
  }
};

// Russian roulette's survival probability for a path of throughput `throughput`: 1.5 times
// the square root of its largest component, in [0.05, 1]. The square root (Cycles') is
// already gentler than the throughput itself; the factor keeps paths a little longer,
// which paid for itself on every converge scene measured (relMSE x render instructions at
// 64 spp, 4 seeds, against 1.0: colour-bleed box -7%, glossy and glass -14%, 1,000
// emissive triangles -9%, 250k-triangle mesh -2%; 2.0 was worse than 1.5 on all three
// where it was tried).
TESSERA_HD TESSERA_INLINE float roulette_survival(const vec3& throughput) {
  return glm::clamp(1.5f * std::sqrt(max_component(throughput)), 0.05f, 1.0f);
}

// A shadow ray crosses at most this many thin films, and a path this many in all; past
// that the light is taken as blocked and the path ends (a guard against endless crossings,
// far beyond any scene's bubbles).
inline constexpr std::uint32_t kMaxFilmCrossings = 32;

// The fraction of light that reaches the end of `ray` (unit direction, t_max its end):
// 1 - R of each thin film it crosses (a film transmits straight on, so a shadow ray may pass
// it), 0 when anything else is in the way. Thin films are found by the closest hits along
// the ray, with kShapes' surfaces.
template <unsigned kShapes, typename T>
TESSERA_HD vec3 film_transmittance(const SceneView& scene, const T& tracer, Ray ray) {
  const vec3 end = ray.origin + ray.t_max * ray.direction;
  vec3 transmittance(1.0f);
  for (std::uint32_t crossing = 0;; ++crossing) {
    HitRecord hit;
    if (!tracer.trace_closest(ray, hit)) return transmittance;
    if (crossing == kMaxFilmCrossings) return vec3(0.0f);
    const SurfaceInteraction si = surface_at<kShapes>(scene, ray, hit);
    const Material& material = scene.materials[si.material];
    if (material.kind != BsdfKind::kThinDielectric) return vec3(0.0f);
    // The reflectance the film's BSDF uses: at the angle to its shading normal.
    const float cos_theta = glm::min(1.0f, std::fabs(glm::dot(ray.direction, si.shading_normal)));
    transmittance *= vec3(1.0f) - thin_film_reflectance(cos_theta, material.exterior_ior,
                                                        material.ior, material.film_thickness_nm);
    const float facing = glm::dot(ray.direction, si.geometric_normal);
    ray.origin =
        offset_ray_origin(si.position, facing < 0.0f ? -si.geometric_normal : si.geometric_normal,
                          scene.spawn_scale, si.position_error);
    ray.t_min = 0.0f;
    ray.t_max = glm::dot(end - ray.origin, ray.direction);
    if (!(ray.t_max > 0.0f)) return transmittance;
  }
}

// A light sample whose shadow ray is not traced yet (prepare_light_sample), and what it
// contributes when the ray arrives (finish_light_sample).
struct ShadowQuery {
  Ray ray;
  vec3 f_li{0.0f};        // f cos Li, before the transmittance and the weight / pdf
  vec3 wi{0.0f};          // towards the light, in the shading frame (the MIS weight's BSDF pdf)
  float pdf = 0.0f;       // of the light sample, pick included
  bool weighted = false;  // weighed against BSDF sampling
  bool pending = false;   // false: no sample, it contributes nothing
};

// The first half of one light's sample at the point (direct_from_light): the direction,
// f cos Li and the shadow ray, everything but the trace, from the point on the light that
// (u1, u2) give. `pmf` is the probability the light was chosen (1 for a light sampled at
// every vertex). The path tracer does the BSDF's own
// sample between the two halves: the light samplers end in chains of dependent square roots
// and divisions that the shadow ray's walk waits on, and work placed before that walk runs
// while they do.
TESSERA_HD inline void prepare_light_sample(const SceneView& scene, const SurfaceInteraction& si,
                                            const Frame& frame, const vec3& wo, const Bsdf& bsdf,
                                            const LightSource& light, float pmf, float u1, float u2,
                                            LightStrategy strategy, const vec3& front_origin,
                                            std::uint32_t& rays, ShadowQuery& query) {
  query.pending = false;
  // BSDF sampling finds every emitter a ray can hit; delta lights only light sampling finds.
  if (strategy == LightStrategy::kBsdf && light.hit_by_rays) return;
  LightSample ls;
  if (!sample_light(scene, light, si.position, u1, u2, ls, si.geometric_normal)) return;
  // Shading normals must not let light through the geometric surface: the light must be on
  // the side the shading frame puts it, and behind the surface only for a BSDF that
  // transmits (rough glass).
  const float side = glm::dot(ls.wi, si.geometric_normal);
  if (side <= 0.0f && !bsdf.has_glossy_transmission()) return;
  const vec3 wi = frame.to_local(ls.wi);
  if ((wi.z > 0.0f) != (side > 0.0f)) return;
  const vec3 f = bsdf.eval(wo, wi) * std::fabs(wi.z);
  if (!(f.x > 0.0f || f.y > 0.0f || f.z > 0.0f)) return;
  const float pdf = pmf * ls.pdf;
  if (!(pdf > 0.0f)) return;
  ++rays;
  const vec3 origin = side > 0.0f ? front_origin
                                  : offset_ray_origin(si.position, -si.geometric_normal,
                                                      scene.spawn_scale, si.position_error);
  // Stop just short of the light so the shadow ray cannot hit the light itself, measured
  // from the offset origin: with ls.wi and ls.distance (measured from si.position) the
  // segment's end, moved by the offset, lies inside a sphere light wherever the sample is
  // near its silhouette, and the light shadowed itself (0.2% too dark on a plane under a
  // sphere light: tests/unit/render/render_accuracy_test.cpp).
  const vec3 to_light = si.position + ls.distance * ls.wi - origin;
  const float length = glm::length(to_light);
  query.ray = Ray{origin, to_light / length, 0.0f, length * (1.0f - 1e-4f)};
  query.f_li = f * ls.radiance;
  query.wi = wi;
  query.pdf = pdf;
  query.weighted = strategy == LightStrategy::kMis && light.hit_by_rays;
  query.pending = true;
}

// The second half: traces the shadow ray and returns f cos Li / pdf, weighted against BSDF
// sampling when the query says so; 0 for no sample.
template <unsigned kFilmShapes, typename T>
TESSERA_HD vec3 finish_light_sample(const SceneView& scene, const vec3& wo, const Bsdf& bsdf,
                                    const T& tracer, const ShadowQuery& query) {
  if (!query.pending) return vec3(0.0f);
  vec3 transmittance(1.0f);
  if constexpr (kFilmShapes != 0) {
    if (scene.thin_films) {
      transmittance = film_transmittance<kFilmShapes>(scene, tracer, query.ray);
      if (!(max_component(transmittance) > 0.0f)) return vec3(0.0f);
    } else if (tracer.occluded(query.ray)) {
      return vec3(0.0f);
    }
  } else {
    if (tracer.occluded(query.ray)) return vec3(0.0f);
  }
  const float weight = query.weighted ? power_heuristic(query.pdf, bsdf.pdf(wo, query.wi)) : 1.0f;
  return query.f_li * transmittance * (weight / query.pdf);
}

// One light's sample at the point for estimate_direct, `pmf` the probability it was chosen
// (1 for a light sampled at every vertex): both halves at once.
template <unsigned kFilmShapes, typename T>
TESSERA_HD vec3 direct_from_light(const SceneView& scene, const SurfaceInteraction& si,
                                  const Frame& frame, const vec3& wo, const Bsdf& bsdf,
                                  const LightSource& light, float pmf, const BounceSamples& u,
                                  LightStrategy strategy, const T& tracer, const vec3& front_origin,
                                  std::uint32_t& rays) {
  ShadowQuery query;
  prepare_light_sample(scene, si, frame, wo, bsdf, light, pmf, u.light_u1, u.light_u2, strategy,
                       front_origin, rays, query);
  return finish_light_sample<kFilmShapes>(scene, wo, bsdf, tracer, query);
}

// Next-event estimation at a surface point up to the picked light's shadow ray: each light
// sampled at every vertex (a few delta lights) in full, then one light picked (light tree
// or power) and its sample prepared in `picked` (finish_light_sample traces it). Returns
// the every-vertex lights' part. Arguments as estimate_direct's.
template <unsigned kFilmShapes, typename T>
TESSERA_HD vec3 begin_direct(const SceneView& scene, const SurfaceInteraction& si,
                             const Frame& frame, const vec3& wo, const Bsdf& bsdf,
                             const BounceSamples& u, LightStrategy strategy, const T& tracer,
                             const vec3& front_origin, std::uint32_t& rays, ShadowQuery& picked) {
  picked.pending = false;
  vec3 direct(0.0f);
  for (std::uint32_t i = 0; i < scene.every_vertex_count; ++i)
    direct += direct_from_light<kFilmShapes>(scene, si, frame, wo, bsdf,
                                             scene.lights[scene.every_vertex_lights[i]], 1.0f, u,
                                             strategy, tracer, front_origin, rays);
  if (!scene.pick_lights) return direct;
  const LightPick pick = pick_light(scene, si.position, si.geometric_normal,
                                    u.pick_with_light_point ? u.light_u1 : u.light_pick);
  if (!(pick.pmf > 0.0f)) return direct;
  prepare_light_sample(scene, si, frame, wo, bsdf, scene.lights[pick.index], pick.pmf,
                       u.pick_with_light_point ? pick.reused_u : u.light_u1, u.light_u2, strategy,
                       front_origin, rays, picked);
  return direct;
}

// Next-event estimation at a surface point: each light sampled at every vertex (a few delta
// lights), then one light picked (light tree or power), one direction towards it by that
// light's sampler, one shadow ray each. Returns f cos Li / pdf, weighted
// against BSDF sampling as `strategy` says. `frame` is the shading frame, `wo` local.
// `front_origin` is si.position moved off the surface to the side of si.geometric_normal
// (offset_ray_origin), which the caller shares with a reflected continuation ray.
// kFilmShapes: the shapes a shadow ray looks for thin films with when the scene has any
// (the path tracer, whose paths pass straight through films: PathHit); 0 makes every
// surface block it (the shadow preview).
template <unsigned kFilmShapes, typename T>
TESSERA_HD vec3 estimate_direct(const SceneView& scene, const SurfaceInteraction& si,
                                const Frame& frame, const vec3& wo, const Bsdf& bsdf,
                                const BounceSamples& u, LightStrategy strategy, const T& tracer,
                                const vec3& front_origin, std::uint32_t& rays) {
  ShadowQuery picked;
  const vec3 direct = begin_direct<kFilmShapes>(scene, si, frame, wo, bsdf, u, strategy, tracer,
                                                front_origin, rays, picked);
  return direct + finish_light_sample<kFilmShapes>(scene, wo, bsdf, tracer, picked);
}

// The Lambertian response (unit albedo) to one light sample at `si`, for the shadow
// preview integrator.
template <typename T>
TESSERA_HD vec3 sample_direct_light(const SceneView& scene, const SurfaceInteraction& si,
                                    SampleStream& rng, const T& tracer, std::uint32_t& rays) {
  if (scene.light_count == 0) return vec3(0.0f);
  BounceSamples u;
  BounceSamples::draw(rng, 0, BouncePair::kLobeAndPick, u.lobe, u.light_pick);
  BounceSamples::draw(rng, 0, BouncePair::kLightPoint, u.light_u1, u.light_u2);
  const Frame frame = Frame::from_normal(si.geometric_normal);
  Bsdf lambert;
  lambert.albedo = vec3(1.0f);
  return estimate_direct<0>(
      scene, si, frame, vec3(0.0f, 0.0f, 1.0f), lambert, u, LightStrategy::kLight, tracer,
      offset_ray_origin(si.position, si.geometric_normal, scene.spawn_scale, si.position_error),
      rays);
}

// The share of light `index`'s radiance, reached by a BSDF-sampled ray in `direction`, that
// a path counts: all of it after a camera ray or a specular bounce, or for an emitter no
// sampler knows (index past the light list); otherwise the previous vertex also sampled that
// light, so the two estimators are weighted as `strategy` says. `distance` and `normal`: where
// the ray met the light (0 and 0 for lights at infinity). Emitter hits and escaping rays share it.
template <typename Payload>
TESSERA_HD float emitter_hit_weight(const SceneView& scene, LightStrategy strategy,
                                    const Payload& payload, std::uint32_t index,
                                    const vec3& direction, float distance, const vec3& normal) {
  if (payload.count_emission || index >= scene.light_count) return 1.0f;
  switch (strategy) {
    case LightStrategy::kBsdf:
      return 1.0f;
    case LightStrategy::kLight:
      return 0.0f;
    case LightStrategy::kMis:
      break;
  }
  const float pdf_light =
      light_pick_pmf(scene, payload.previous_position, payload.previous_normal, index) *
      light_pdf(scene, scene.lights[index], payload.previous_position, direction, distance, normal,
                payload.previous_normal);
  return power_heuristic(payload.previous_pdf, pdf_light);
}

template <PipelineFeatures kFeatures>
struct PathHit {
  // The scene (1,192 bytes): the caller's, which outlives the program object. A copy would put
  // these bytes on every GPU thread's stack (local memory): by reference the kernel reads its
  // __grid_constant__ parameter through the constant cache.
  const SceneView& scene;
  std::uint32_t max_depth;
  LightStrategy strategy = LightStrategy::kMis;
  float clamp = 0.0f;  // RenderSettings::clamp, see clamp_indirect

  template <typename T>
  TESSERA_HD void on_hit(const Ray& ray, const HitRecord& hit, PathPayload<kFeatures.aovs>& payload,
                         const T& tracer) const {
    SurfaceInteraction si = surface_at<kFeatures.shapes>(scene, ray, hit);
    apply_golf_dimples(scene, scene.materials[si.material], hit.primitive, ray, si);
    const float distance = hit.t * glm::length(ray.direction);
    const float footprint = payload.cone_width + payload.cone_spread * distance;
    MaterialScratch textured;
    const Material& material =
        material_at(scene, scene.materials[si.material], hit.primitive, si, footprint, textured);
    const vec3 albedo = albedo_at(scene, material, hit.primitive, si, footprint);
    // Leaving absorbing glass: the segment just traced ran inside it (closed, not nested).
    if (!si.front_face && material.kind == BsdfKind::kDielectric && material.absorbs())
      payload.throughput *= glm::exp(-material.absorption * distance);
    if constexpr (kFeatures.aovs) {
      if (payload.depth == 0) {
        payload.aov.albedo = albedo;
        payload.aov.normal = si.shading_normal;
        payload.aov.depth = distance;
        payload.aov.primitive = hit.primitive;
      }
    }
    const std::uint32_t bounces = payload.bounces();
    if (material.emissive())
      payload.radiance += clamp_indirect(
          payload.throughput * material.emission * emission_weight(ray, hit, si, payload), clamp,
          bounces >= 2);
    if (material.kind == BsdfKind::kEmitter) return;
    // Unlit materials end the path with their colour, at any depth, as RayON's do.
    if (material.unlit()) {
      payload.radiance += payload.throughput * material.unlit_color(albedo, si.shading_normal);
      return;
    }
    if constexpr (kFeatures.specular) {
      if (material.kind == BsdfKind::kThinDielectric &&
          cross_film(ray, si, material, footprint, payload))
        return;
    }
    if (bounces + 1 >= max_depth) return;

    const vec3 ng = si.geometric_normal;  // faces the incoming ray
    // The spawn point on ng's side, for the shadow ray and a reflected continuation alike.
    const vec3 front_origin =
        offset_ray_origin(si.position, ng, scene.spawn_scale, si.position_error);
    Bsdf bsdf = Bsdf::of(material, si.front_face, albedo);
    // Formed in place rather than picked by a conditional expression: from that GCC stored
    // the normal as an 8- and a 4-byte store and read it back at once as one 8-byte load
    // across both, which has to wait for the stores to reach the cache (1% of two_lights'
    // samples). store_ray says more.
    Frame frame = Frame::from_normal(si.shading_normal);
    if (bsdf.anisotropic()) [[unlikely]]
      frame =
          Frame::from_normal_and_tangent(si.shading_normal, anisotropy_tangent(si.shading_normal));
    const vec3 wo = frame.to_local(-ray.direction);
    // Variants without specular materials compile the Lambertian case alone.
    if constexpr (!kFeatures.specular) bsdf.kind = BsdfKind::kDiffuse;
    BounceSamples u;
    bool sample_lights = false;
    if constexpr (kFeatures.direct_lighting)
      sample_lights = scene.light_count > 0 && bsdf.has_non_specular();
    SampleStream& rng = payload.samples;
    // The (lobe, light pick) pair is drawn only for a BSDF with more than one lobe; a
    // diffuse vertex picks its light with the light point's first coordinate
    // (BounceSamples::pick_with_light_point) and skips a third of its samples' cost.
    if (bsdf.kind != BsdfKind::kDiffuse)
      BounceSamples::draw(rng, payload.depth, BouncePair::kLobeAndPick, u.lobe, u.light_pick);
    else
      u.pick_with_light_point = true;
    // Next-event estimation in two halves with the BSDF's sample between them, so that
    // it runs while the light sample's square roots and divisions are still in flight
    // (prepare_light_sample); the picked light's shadow ray is traced after it.
    vec3 direct(0.0f);
    ShadowQuery picked;
    if (sample_lights) {
      BounceSamples::draw(rng, payload.depth, BouncePair::kLightPoint, u.light_u1, u.light_u2);
      direct = begin_direct<kFeatures.shapes>(scene, si, frame, wo, bsdf, u, strategy, tracer,
                                              front_origin, payload.rays, picked);
    }
    BounceSamples::draw(rng, payload.depth, BouncePair::kBsdfDirection, u.bsdf_u1, u.bsdf_u2);
    const BsdfSample bs = bsdf.sample(wo, u.lobe, u.bsdf_u1, u.bsdf_u2);
    if (sample_lights) {
      direct += finish_light_sample<kFeatures.shapes>(scene, wo, bsdf, tracer, picked);
      payload.radiance += clamp_indirect(payload.throughput * direct, clamp, bounces >= 1);
    }
    if (!bs.valid()) return;
    const vec3 direction = frame.to_world(bs.wi);
    // A reflection must leave on the side the path came from, a transmission on the other;
    // interpolated normals can disagree with the surface, and then the path is absorbed.
    const float side = glm::dot(direction, ng);
    if ((bs.lobe & kLobeReflection) != 0 ? side <= 0.0f : side >= 0.0f) return;
    payload.throughput *= bs.weight();
    payload.previous_pdf = bs.pdf;
    payload.previous_position = si.position;
    payload.previous_normal = ng;
    // Camera rays and specular bounces are the only way to see an emitter directly; with
    // no light list, so is every bounce.
    payload.count_emission = bs.specular() || !kFeatures.direct_lighting;
    // A specular bounce keeps the cone's spread (flat mirrors and glass); a glossy or
    // diffuse one widens it by about its lobe's angular width, so textures seen only
    // through rough or diffuse bounces are read from coarse levels.
    payload.cone_width = footprint;
    if (!bs.specular())
      payload.cone_spread += bsdf.kind == BsdfKind::kDiffuse
                                 ? 0.5f
                                 : 2.0f * glm::max(material.alpha_x, material.alpha_y);

    // Russian roulette keeps long paths unbiased without tracing every one to max depth
    // (roulette_survival says how gently). Starting it at the third vertex beat the first
    // and second on the colour-bleed box; no roulette at all cost 39% more per unit of
    // error there.
    ++payload.depth;
    if (bounces + 1 >= 3) {
      const float survive = roulette_survival(payload.throughput);
      if (BounceSamples::roulette(rng, payload.depth - 1) >= survive) return;
      payload.throughput /= survive;
    }
    const vec3 origin =
        side >= 0.0f ? front_origin
                     : offset_ray_origin(si.position, -ng, scene.spawn_scale, si.position_error);
    store_ray(payload.next_ray, origin, direction, 0.0f, kInfinity);
    payload.has_next_ray = true;
    ++payload.rays;
  }

 private:
  // The share of an emitter's radiance this hit counts. Camera rays and specular bounces
  // count it all; after a BSDF sample the light was also sampled at the previous vertex
  // (when it is in the light list), so the two are weighted as `strategy` says.
  TESSERA_HD float emission_weight(const Ray& ray, const HitRecord& hit,
                                   const SurfaceInteraction& si,
                                   const PathPayload<kFeatures.aovs>& payload) const {
    if constexpr (!kFeatures.direct_lighting) {
      return 1.0f;
    } else {
      if (payload.count_emission) return 1.0f;
      const std::uint32_t index = find_light(scene, hit.primitive);
      const float distance = glm::length(si.position - payload.previous_position);
      return emitter_hit_weight(scene, strategy, payload, index, ray.direction, distance,
                                si.geometric_normal);
    }
  }

  // A thin film reflects R or transmits 1 - R straight on (Bsdf's thin-film lobes, picked by
  // the same sample and probability). Crossing it is no scattering vertex: the path keeps its
  // previous vertex, so an emitter seen through films is weighed against the light sample taken
  // there, whose shadow ray crossed the same films (film_transmittance), and the crossing
  // does not count towards max_depth (Cycles counts such transparent bounces apart too).
  // Without this a floor under soap bubbles was lit only by BSDF samples that happened to
  // pass through a bubble to the light. Returns whether it crossed (the next ray is set).
  TESSERA_HD bool cross_film(const Ray& ray, const SurfaceInteraction& si, const Material& material,
                             float footprint, PathPayload<kFeatures.aovs>& payload) const {
    const vec3 wo = Frame::from_normal(si.shading_normal).to_local(-ray.direction);
    const vec3 r = thin_film_reflectance(wo.z, material.exterior_ior, material.ior,
                                         material.film_thickness_nm);
    const float reflect = thin_film_reflect_probability(r);
    float u_lobe, u_unused;
    BounceSamples::draw(payload.samples, payload.depth, BouncePair::kLobeAndPick, u_lobe, u_unused);
    if (u_lobe < reflect || !(wo.z > 0.0f)) return false;  // reflected: an ordinary vertex
    if (payload.film_crossings + 1 >= kMaxFilmCrossings) return true;  // ends the path
    payload.throughput *= (vec3(1.0f) - r) / (1.0f - reflect);
    ++payload.depth;
    ++payload.film_crossings;
    payload.cone_width = footprint;
    store_ray(
        payload.next_ray,
        offset_ray_origin(si.position, -si.geometric_normal, scene.spawn_scale, si.position_error),
        ray.direction, 0.0f, kInfinity);
    payload.has_next_ray = true;
    ++payload.rays;
    return true;
  }
};

// The path tracer's miss program: an escaping ray sees the environment and any distant
// light with an angular radius it points into. Those are in the light list too, so after a
// BSDF sample their radiance is weighted against light sampling at the previous vertex, as
// an emitter hit is (PathHit::emission_weight).
template <PipelineFeatures kFeatures>
struct PathMiss {
  // The scene (1,192 bytes): the caller's, which outlives the program object. A copy would put
  // these bytes on every GPU thread's stack (local memory): by reference the kernel reads its
  // __grid_constant__ parameter through the constant cache.
  const SceneView& scene;
  LightStrategy strategy = LightStrategy::kMis;
  // Camera rays that miss add nothing (the environment still lights the scene).
  bool transparent_background = false;
  float clamp = 0.0f;  // RenderSettings::clamp

  TESSERA_HD void on_miss(const Ray& ray, PathPayload<kFeatures.aovs>& payload) const {
    if (payload.depth == 0) {
      payload.coverage = 0.0f;
      if (transparent_background) return;
    }
    const vec3 direction = glm::normalize(ray.direction);
    vec3 seen =
        scene.environment.radiance(direction) * weight(payload, scene.environment_light, direction);
    if constexpr (kFeatures.direct_lighting) {
      // Suns with an extent are few (each is one light); test each cone.
      for (std::uint32_t i = 0; i < scene.analytic_light_count; ++i) {
        const AnalyticLight& light = scene.analytic_lights[i];
        if (!distant_with_extent(light) || !in_distant_cone(light, direction)) continue;
        seen +=
            distant_radiance(light) * weight(payload, scene.first_analytic_light + i, direction);
      }
    }
    payload.radiance += clamp_indirect(payload.throughput * seen, clamp, payload.bounces() >= 2);
  }

 private:
  TESSERA_HD float weight(const PathPayload<kFeatures.aovs>& payload, std::uint32_t index,
                          const vec3& direction) const {
    if constexpr (!kFeatures.direct_lighting) {
      return 1.0f;
    } else {
      return emitter_hit_weight(scene, strategy, payload, index, direction, 0.0f, vec3(0.0f));
    }
  }
};

template <PipelineFeatures kFeatures>
struct PathTracerConfig {
  using RayGeneration = PathRayGeneration<kFeatures.aovs>;
  using Intersection = SceneIntersection<kFeatures.shapes>;
  using Hit = PathHit<kFeatures>;
  using Miss = PathMiss<kFeatures>;
};

}  // namespace tessera
