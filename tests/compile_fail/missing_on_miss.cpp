// Must NOT compile: the configuration's miss program has no on_miss. The test checks that
// the compiler's message names the missing function.
#include "tessera/pipeline/pipeline.hpp"

namespace {

struct Payload {
  bool has_next_ray = false;
  tessera::Ray next_ray;
};

struct Generate {
  using Payload = ::Payload;
  tessera::Ray generate(std::uint32_t, std::uint32_t, std::uint32_t, Payload&) const { return {}; }
  void on_result(std::uint32_t, std::uint32_t, std::uint32_t, const Payload&) const {}
};

struct Intersect {
  bool intersect(std::uint32_t, const tessera::Ray&, float, tessera::HitRecord&) const {
    return false;
  }
};

struct Shade {
  template <typename T>
  void on_hit(const tessera::Ray&, const tessera::HitRecord&, Payload&, const T&) const {}
};

struct NoMissFunction {
  void on_missed_ray(const tessera::Ray&, Payload&) const {}
};

struct Config {
  using RayGeneration = Generate;
  using Intersection = Intersect;
  using Hit = Shade;
  using Miss = NoMissFunction;
};

}  // namespace

void instantiate(tessera::BvhView bvh) {
  const tessera::Pipeline<Config> pipeline(
      Generate{}, tessera::BvhTracer<Intersect>(bvh, Intersect{}), Shade{}, NoMissFunction{});
  pipeline.launch(0, 0, 0);
}
