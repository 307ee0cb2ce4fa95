#pragma once
#include <cstdint>

#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/pipeline/concepts.hpp"

namespace tessera {

// The traversal stage: an acceleration structure walked with the configuration's
// intersection program. Closest-hit and any-hit are separate instantiations, so a shadow
// ray's early exit is compiled in, not tested per node.
template <IntersectionProgram Intersection>
class BvhTracer {
 public:
  TESSERA_HD BvhTracer(BvhView bvh, Intersection intersection)
      : bvh_(bvh), intersection_(intersection) {}

  TESSERA_HD bool trace_closest(const Ray& ray, HitRecord& hit) const {
    hit.t = ray.t_max;
    return traverse_bvh<false>(
        bvh_, ray, hit, [this](std::uint32_t primitive, const Ray& r, float t_max, HitRecord& h) {
          return intersection_.intersect(primitive, r, t_max, h);
        });
  }
  TESSERA_HD bool occluded(const Ray& ray) const {
    HitRecord hit;
    hit.t = ray.t_max;
    return traverse_bvh<true>(
        bvh_, ray, hit, [this](std::uint32_t primitive, const Ray& r, float t_max, HitRecord& h) {
          return intersection_.intersect(primitive, r, t_max, h);
        });
  }

 private:
  BvhView bvh_;
  Intersection intersection_;
};

// A pipeline configuration names its programs:
//   struct Config {
//     using RayGeneration = ...;  using Intersection = ...;
//     using Hit = ...;            using Miss = ...;
//   };
template <typename C>
concept PipelineConfig = RayGenerationProgram<typename C::RayGeneration> &&
    IntersectionProgram<typename C::Intersection> &&
    ContinuablePayload<typename C::RayGeneration::Payload> &&
    HitProgram<typename C::Hit, typename C::RayGeneration::Payload,
               BvhTracer<typename C::Intersection>> &&
    MissProgram<typename C::Miss, typename C::RayGeneration::Payload>;

// Composes the four stages. Everything is a template parameter, so the compiler sees the
// whole path from ray generation to shading and inlines it: no virtual calls, nothing
// allocated per ray. Paths of many bounces run as continuation rays in a loop.
template <PipelineConfig Config>
class Pipeline {
 public:
  using RayGeneration = typename Config::RayGeneration;
  using Payload = typename RayGeneration::Payload;

  TESSERA_HD Pipeline(typename Config::RayGeneration ray_generation,
                      BvhTracer<typename Config::Intersection> tracer, typename Config::Hit hit,
                      typename Config::Miss miss)
      : ray_generation_(ray_generation), tracer_(tracer), hit_(hit), miss_(miss) {}

  // Runs one sample of one pixel to completion.
  TESSERA_HD void launch(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    Payload payload{};
    Ray ray = ray_generation_.generate(x, y, sample, payload);
    for (;;) {
      payload.has_next_ray = false;
      HitRecord hit;
      if (tracer_.trace_closest(ray, hit)) {
        hit_.on_hit(ray, hit, payload, tracer_);
      } else {
        miss_.on_miss(ray, payload);
      }
      if (!payload.has_next_ray) break;
      ray = payload.next_ray;
    }
    ray_generation_.on_result(x, y, sample, payload);
  }

  TESSERA_HD const BvhTracer<typename Config::Intersection>& tracer() const { return tracer_; }

 private:
  RayGeneration ray_generation_;
  BvhTracer<typename Config::Intersection> tracer_;
  typename Config::Hit hit_;
  typename Config::Miss miss_;
};

}  // namespace tessera
