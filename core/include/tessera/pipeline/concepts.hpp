#pragma once
#include <concepts>
#include <cstdint>

#include "tessera/geometry/ray.hpp"

namespace tessera {

// The four program kinds of the pipeline, after GPU ray tracing pipelines: ray generation
// makes rays and receives their results, intersection tests primitives, hit and miss
// programs shade. A configuration that lacks a required function fails to compile at the
// concept check, which names the missing requirement.

// Anything that can trace: what hit programs receive so they can cast shadow rays.
template <typename T>
concept Tracer = requires(const T& tracer, const Ray& ray, HitRecord& hit) {
  { tracer.trace_closest(ray, hit) } -> std::same_as<bool>;
  { tracer.occluded(ray) } -> std::same_as<bool>;
};

// A payload that can ask for a continuation ray instead of recursing.
template <typename P>
concept ContinuablePayload = requires(P& payload) {
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

template <typename I>
concept IntersectionProgram = requires(const I& program, std::uint32_t primitive, const Ray& ray,
                                       float t_max, HitRecord& hit) {
  { program.intersect(primitive, ray, t_max, hit) } -> std::same_as<bool>;
};

template <typename H, typename Payload, typename T>
concept HitProgram = requires(const H& program, const Ray& ray, const HitRecord& hit,
                              Payload& payload, const T& tracer) {
  {program.on_hit(ray, hit, payload, tracer)};
};

template <typename M, typename Payload>
concept MissProgram = requires(const M& program, const Ray& ray, Payload& payload) {
  {program.on_miss(ray, payload)};
};

}  // namespace tessera
