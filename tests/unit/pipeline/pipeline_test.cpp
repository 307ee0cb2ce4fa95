#include "tessera/pipeline/pipeline.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "tessera/geometry/sphere.hpp"

namespace tessera {
namespace {

// A row of unit spheres along +z at z = 5, 10, 15, ...; rays start at the origin.
struct RowOfSpheres {
  std::vector<Sphere> spheres;
  Bvh bvh;

  explicit RowOfSpheres(int count) {
    std::vector<Aabb> boxes;
    std::vector<std::uint32_t> refs;
    for (int i = 0; i < count; ++i) {
      spheres.push_back(Sphere{vec3(0, 0, 5.0f * (i + 1)), 1.0f, static_cast<std::uint32_t>(i)});
      boxes.push_back(bounds(spheres.back()));
      refs.push_back(static_cast<std::uint32_t>(i));
    }
    bvh = build_bvh(boxes, refs);
  }
};

struct SphereIntersection {
  const Sphere* spheres;
  bool intersect(std::uint32_t primitive, const Ray& ray, float t_max, HitRecord& hit) const {
    return tessera::intersect(spheres[primitive], ray, t_max, hit, primitive);
  }
};

struct Payload {
  std::vector<float>* log;
  int bounces = 0;
  bool initialised = false;
  bool has_next_ray = false;
  Ray next_ray;
};

struct RecordingRayGeneration {
  using Payload = tessera::Payload;
  std::vector<float>* log;
  int* results;
  void init_payload(std::uint32_t, std::uint32_t, std::uint32_t, Payload& p) const {
    p.initialised = true;
  }
  Ray generate(std::uint32_t, std::uint32_t, std::uint32_t, Payload& p) const {
    EXPECT_TRUE(p.initialised) << "init_payload must run before generate";
    p.log = log;
    return Ray{vec3(0.0f), vec3(0, 0, 1), 0.0f, kInfinity};
  }
  void on_result(std::uint32_t, std::uint32_t, std::uint32_t, const Payload&) const { ++*results; }
};

// Logs the hit distance and continues the ray just beyond it: a path of many bounces
// without recursion.
struct ContinueThrough {
  template <typename T>
  void on_hit(const Ray& ray, const HitRecord& hit, Payload& p, const T&) const {
    p.log->push_back(hit.t);
    ++p.bounces;
    p.next_ray = Ray{ray.origin, ray.direction, hit.t + 1e-3f, kInfinity};
    p.has_next_ray = true;
  }
};

struct LogMiss {
  void on_miss(const Ray&, Payload& p) const { p.log->push_back(-1.0f); }
};

struct ContinuationConfig {
  using RayGeneration = RecordingRayGeneration;
  using Intersection = SphereIntersection;
  using Hit = ContinueThrough;
  using Miss = LogMiss;
};

TEST(Pipeline, ContinuationRaysVisitEverySurfaceInOrderThenMiss) {
  RowOfSpheres row(3);
  std::vector<float> log;
  int results = 0;
  const Pipeline<ContinuationConfig> pipeline(
      RecordingRayGeneration{&log, &results},
      BvhTracer<SphereIntersection>(row.bvh.view(), {row.spheres.data()}), ContinueThrough{},
      LogMiss{});
  pipeline.launch(0, 0, 0);
  const std::vector<float> expected = {4, 6, 9, 11, 14, 16, -1};
  ASSERT_EQ(log.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(log[i], expected[i], 1e-4f);
  EXPECT_EQ(results, 1);
}

struct MultiHitLogger {
  template <typename T>
  void on_hits(const Ray&, const HitRecord* hits, int count, Payload& p, const T&) const {
    for (int i = 0; i < count; ++i) p.log->push_back(hits[i].t);
  }
};

template <int kHits>
struct MultiHitConfig {
  using RayGeneration = RecordingRayGeneration;
  using Intersection = SphereIntersection;
  using Hit = MultiHitLogger;
  using Miss = LogMiss;
  static constexpr int kMaxHits = kHits;
};

TEST(Pipeline, MultiHitReturnsTheNearestHitsSortedByT) {
  RowOfSpheres row(6);
  std::vector<float> log;
  int results = 0;
  // Without intersect_all the program reports the entry point of each sphere.
  const Pipeline<MultiHitConfig<4>> pipeline(
      RecordingRayGeneration{&log, &results},
      BvhTracer<SphereIntersection>(row.bvh.view(), {row.spheres.data()}), MultiHitLogger{},
      LogMiss{});
  pipeline.launch(0, 0, 0);
  const std::vector<float> expected = {4, 9, 14, 19};
  ASSERT_EQ(log.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(log[i], expected[i], 1e-4f);
}

struct SphereIntersectionAll : SphereIntersection {
  int intersect_all(std::uint32_t primitive, const Ray& ray, float t_max, HitRecord* hits,
                    int max_hits) const {
    if (max_hits < 1 || !intersect(primitive, ray, t_max, hits[0])) return 0;
    Ray beyond = ray;
    beyond.t_min = hits[0].t;
    return max_hits > 1 && intersect(primitive, beyond, t_max, hits[1]) ? 2 : 1;
  }
};

struct MultiHitAllConfig {
  using RayGeneration = RecordingRayGeneration;
  using Intersection = SphereIntersectionAll;
  using Hit = MultiHitLogger;
  using Miss = LogMiss;
  static constexpr int kMaxHits = 5;
};

TEST(Pipeline, MultiHitUsesIntersectAllForEveryCrossing) {
  RowOfSpheres row(4);
  std::vector<float> log;
  int results = 0;
  const Pipeline<MultiHitAllConfig> pipeline(
      RecordingRayGeneration{&log, &results},
      BvhTracer<SphereIntersectionAll>(row.bvh.view(), {{row.spheres.data()}}), MultiHitLogger{},
      LogMiss{});
  pipeline.launch(0, 0, 0);
  const std::vector<float> expected = {4, 6, 9, 11, 14};
  ASSERT_EQ(log.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(log[i], expected[i], 1e-4f);
}

struct StopAtFirst {
  template <typename T>
  void on_hit(const Ray&, const HitRecord& hit, Payload& p, const T&) const {
    p.log->push_back(hit.t);
  }
};

struct AnyHitConfig {
  using RayGeneration = RecordingRayGeneration;
  using Intersection = SphereIntersection;
  using Hit = StopAtFirst;
  using Miss = LogMiss;
  static constexpr bool kFirstHitOnly = true;
};

TEST(Pipeline, AnyHitConfigurationReportsSomeHitAndOccludedAgrees) {
  RowOfSpheres row(8);
  std::vector<float> log;
  int results = 0;
  const BvhTracer<SphereIntersection> tracer(row.bvh.view(), {row.spheres.data()});
  const Pipeline<AnyHitConfig> pipeline(RecordingRayGeneration{&log, &results}, tracer,
                                        StopAtFirst{}, LogMiss{});
  pipeline.launch(0, 0, 0);
  ASSERT_EQ(log.size(), 1u);
  // Some sphere's entry point: 5k - 1 for k in 1..8.
  const float k = (log[0] + 1.0f) / 5.0f;
  EXPECT_NEAR(k, std::round(k), 1e-4f);
  EXPECT_TRUE(tracer.occluded(Ray{vec3(0.0f), vec3(0, 0, 1), 0.0f, 100.0f}));
  EXPECT_FALSE(tracer.occluded(Ray{vec3(0.0f), vec3(0, 0, 1), 0.0f, 3.9f}));
  EXPECT_FALSE(tracer.occluded(Ray{vec3(0.0f), vec3(0, 1, 0), 0.0f, 100.0f}));
}

}  // namespace
}  // namespace tessera
