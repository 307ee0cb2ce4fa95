#pragma once
#include <concepts>
#include <cstdint>

#include "tessera/geometry/ray.hpp"

namespace tessera {

// The program kinds of the pipeline, after GPU ray tracing pipelines: ray generation makes
// rays and receives their results, intersection tests primitives, hit and miss programs
// shade. Each is a concept, so a configuration that lacks a required function fails at
// the concept check, and the compiler's note names the unsatisfied requirement.

// What hit programs receive so they can cast further rays (shadow rays, probes).
template <typename T>
concept Tracer = requires(const T& tracer, const Ray& ray, HitRecord& hit) {
  { tracer.trace_closest(ray, hit) } -> std::same_as<bool>;
  { tracer.occluded(ray) } -> std::same_as<bool>;
};

// Payloads carry a continuation ray instead of recursing: a hit program that wants
// another bounce sets has_next_ray and next_ray, and the pipeline loops.
template <typename P>
concept ContinuablePayload = std::default_initializable<P> && requires(P& payload) {
  { payload.has_next_ray } -> std::convertible_to<bool>;
  { payload.next_ray } -> std::convertible_to<Ray>;
};

template <typename G>
concept RayGenerationProgram = requires(const G& gen, typename G::Payload& payload, std::uint32_t x,
                                        std::uint32_t y, std::uint32_t sample) {
  typename G::Payload;
  { gen.generate(x, y, sample, payload) } -> std::same_as<Ray>;
  {gen.on_result(x, y, sample, payload)};
};

// Optional: prepares a payload before generate(), e.g. to seed its sampler.
template <typename G>
concept HasInitPayload = requires(const G& gen, typename G::Payload& payload, std::uint32_t x,
                                  std::uint32_t y, std::uint32_t sample) {
  {gen.init_payload(x, y, sample, payload)};
};

template <typename I>
concept IntersectionProgram = requires(const I& program, std::uint32_t primitive, const Ray& ray,
                                       float t_max, HitRecord& hit) {
  { program.intersect(primitive, ray, t_max, hit) } -> std::same_as<bool>;
};

// Optional: every hit of one primitive in (t_min, t_max), for multi-hit queries. Without
// it a multi-hit pipeline records only the nearest hit of each primitive.
template <typename I>
concept HasIntersectAll = requires(const I& program, std::uint32_t primitive, const Ray& ray,
                                   float t_max, HitRecord* hits, int max_hits) {
  { program.intersect_all(primitive, ray, t_max, hits, max_hits) } -> std::same_as<int>;
};

template <typename H, typename Payload, typename T>
concept HitProgram = requires(const H& program, const Ray& ray, const HitRecord& hit,
                              Payload& payload, const T& tracer) {
  {program.on_hit(ray, hit, payload, tracer)};
};

// Multi-hit programs receive every hit along the ray, sorted by t.
template <typename H, typename Payload, typename T>
concept MultiHitProgram = requires(const H& program, const Ray& ray, const HitRecord* hits,
                                   int count, Payload& payload, const T& tracer) {
  {program.on_hits(ray, hits, count, payload, tracer)};
};

template <typename M, typename Payload>
concept MissProgram = requires(const M& program, const Ray& ray, Payload& payload) {
  {program.on_miss(ray, payload)};
};

}  // namespace tessera
