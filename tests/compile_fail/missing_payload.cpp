// Must NOT compile: the ray generation program has no generate(). The test checks that
// the compiler's message names it.
#include "tessera/pipeline/pipeline.hpp"

namespace {

struct Payload {
  bool has_next_ray = false;
  tessera::Ray next_ray;
};

struct NoGenerate {
  using Payload = ::Payload;
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

struct Miss {
  void on_miss(const tessera::Ray&, Payload&) const {}
};

struct Config {
  using RayGeneration = NoGenerate;
  using Intersection = Intersect;
  using Hit = Shade;
  using Miss = ::Miss;
};

}  // namespace

void instantiate(tessera::BvhView bvh) {
  const tessera::Pipeline<Config> pipeline(
      NoGenerate{}, tessera::BvhTracer<Intersect>(bvh, Intersect{}), Shade{}, Miss{});
  pipeline.launch(0, 0, 0);
}
