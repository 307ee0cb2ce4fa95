#pragma once
#include <cstdint>

#include "tessera/pipeline/bvh_tracer.hpp"
#include "tessera/pipeline/concepts.hpp"

namespace tessera {

// A pipeline configuration names its programs and options:
//   struct Config {
//     using RayGeneration = ...;  using Intersection = ...;
//     using Hit = ...;            using Miss = ...;
//     static constexpr int kMaxHits = 8;  // optional: multi-hit, Hit has on_hits()
//     static constexpr bool kFirstHitOnly = true;  // optional: any-hit early termination
//   };
namespace pipeline_detail {
template <typename C>
constexpr int max_hits() {
  if constexpr (requires { C::kMaxHits; }) {
    return C::kMaxHits;
  } else {
    return 0;
  }
}
template <typename C>
constexpr bool first_hit_only() {
  if constexpr (requires { C::kFirstHitOnly; }) {
    return C::kFirstHitOnly;
  } else {
    return false;
  }
}
}  // namespace pipeline_detail

template <typename C>
concept PipelineConfig = RayGenerationProgram<typename C::RayGeneration> &&
    IntersectionProgram<typename C::Intersection> &&
    ContinuablePayload<typename C::RayGeneration::Payload> &&
    MissProgram<typename C::Miss, typename C::RayGeneration::Payload> &&
    (pipeline_detail::max_hits<C>() > 0
         ? MultiHitProgram<typename C::Hit, typename C::RayGeneration::Payload,
                           BvhTracer<typename C::Intersection>>
         : HitProgram<typename C::Hit, typename C::RayGeneration::Payload,
                      BvhTracer<typename C::Intersection>>);

// Composes the four stages. Everything is a template parameter, so the compiler sees the
// whole path from ray generation to shading and inlines it: no virtual calls, nothing
// allocated per ray. Paths of many bounces run as continuation rays in a loop.
template <typename Config>
class Pipeline {
  // Checked here rather than in the template head so each missing piece gets its own
  // readable message.
  static_assert(
      RayGenerationProgram<typename Config::RayGeneration>,
      "Config::RayGeneration needs a Payload type, Ray generate(x, y, sample, Payload&) const and "
      "on_result(x, y, sample, const Payload&) const");
  static_assert(IntersectionProgram<typename Config::Intersection>,
                "Config::Intersection needs bool intersect(primitive, const Ray&, float t_max, "
                "HitRecord&) const");
  static_assert(ContinuablePayload<typename Config::RayGeneration::Payload>,
                "the Payload needs bool has_next_ray and Ray next_ray for continuation rays");
  static_assert(MissProgram<typename Config::Miss, typename Config::RayGeneration::Payload>,
                "Config::Miss needs on_miss(const Ray&, Payload&) const");
  static_assert(
      pipeline_detail::max_hits<Config>() > 0 ||
          HitProgram<typename Config::Hit, typename Config::RayGeneration::Payload,
                     BvhTracer<typename Config::Intersection>>,
      "Config::Hit needs on_hit(const Ray&, const HitRecord&, Payload&, const Tracer&) const");
  static_assert(
      pipeline_detail::max_hits<Config>() == 0 ||
          MultiHitProgram<typename Config::Hit, typename Config::RayGeneration::Payload,
                          BvhTracer<typename Config::Intersection>>,
      "a multi-hit Config::Hit needs on_hits(const Ray&, const HitRecord*, int, Payload&, const "
      "Tracer&) const");

 public:
  using RayGeneration = typename Config::RayGeneration;
  using Payload = typename RayGeneration::Payload;
  using TracerType = BvhTracer<typename Config::Intersection>;
  static constexpr int kMaxHits = pipeline_detail::max_hits<Config>();
  static constexpr bool kFirstHitOnly = pipeline_detail::first_hit_only<Config>();

  TESSERA_HD Pipeline(RayGeneration ray_generation, TracerType tracer, typename Config::Hit hit,
                      typename Config::Miss miss)
      : ray_generation_(ray_generation), tracer_(tracer), hit_(hit), miss_(miss) {}

  // Runs one sample of one pixel to completion.
  TESSERA_HD void launch(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    Payload payload{};
    if constexpr (HasInitPayload<RayGeneration>)
      ray_generation_.init_payload(x, y, sample, payload);
    Ray ray = ray_generation_.generate(x, y, sample, payload);
    for (RayKind kind = RayKind::kCamera;; kind = RayKind::kSecondary) {
      payload.has_next_ray = false;
      trace_and_shade(ray, kind, payload);
      if (!payload.has_next_ray) break;
      ray = payload.next_ray;
    }
    ray_generation_.on_result(x, y, sample, payload);
  }

  TESSERA_HD const TracerType& tracer() const { return tracer_; }

 private:
  TESSERA_HD void trace_and_shade(const Ray& ray, RayKind kind, Payload& payload) const {
    if constexpr (kMaxHits > 0) {
      HitRecord hits[kMaxHits];
      const int count = tracer_.template trace_all<kMaxHits>(ray, hits, kind);
      if (count > 0) {
        hit_.on_hits(ray, hits, count, payload, tracer_);
      } else {
        miss_.on_miss(ray, payload);
      }
    } else {
      HitRecord hit;
      bool found;
      if constexpr (kFirstHitOnly) {
        found = tracer_.trace_any(ray, hit, kind);
      } else {
        found = tracer_.trace_closest(ray, hit, kind);
      }
      if (found) {
        hit_.on_hit(ray, hit, payload, tracer_);
      } else {
        miss_.on_miss(ray, payload);
      }
    }
  }

  RayGeneration ray_generation_;
  TracerType tracer_;
  typename Config::Hit hit_;
  typename Config::Miss miss_;
};

}  // namespace tessera
