// Micro-benchmarks of the intersectors: ns per ray for rays that hit and rays that miss.
// Miss rays pass through the shape's bounding sphere (the expensive kind of miss: a ray
// that misses the bounding box never reaches the intersector in a BVH). Each benchmark
// cycles through 1024 precomputed rays so branch prediction cannot learn one ray.
//   tessera-bench-geometry [--benchmark_filter=REGEX]
#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "tessera/geometry/cone.hpp"
#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/disk.hpp"
#include "tessera/geometry/instance.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/sphere_tracing.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/torus.hpp"
#include "tessera/geometry/triangle.hpp"
#include "tessera/geometry/triangle_precise.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/math/solver_bracketed.hpp"
#include "tessera/math/solver_quartic.hpp"

namespace {

using namespace tessera;

constexpr int kRays = 1024;

struct RaySets {
  std::vector<Ray> hits, misses;
};

// Rays from random origins 3-6 bounding radii away aimed at random points of the bounding
// sphere, sorted into hits and misses by the intersector itself.
template <typename Intersect>
RaySets make_rays(const dvec3& center, double radius, Intersect&& intersect_fn,
                  std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto in_ball = [&] {
    for (;;) {
      const dvec3 p(u(rng), u(rng), u(rng));
      if (glm::dot(p, p) <= 1.0) return p;
    }
  };
  RaySets sets;
  for (int attempt = 0;
       attempt < 10000000 && (sets.hits.size() < kRays || sets.misses.size() < kRays); ++attempt) {
    const dvec3 origin =
        center + glm::normalize(in_ball()) * (radius * (3.0 + 3.0 * std::fabs(u(rng))));
    // Targets a bit beyond the bounding sphere so that convex shapes are also missed.
    const dvec3 target = center + in_ball() * (1.3 * radius);
    const Ray ray{vec3(origin), vec3(glm::normalize(target - origin)), 0.0f, kInfinity};
    HitRecord hit;
    std::vector<Ray>& bucket = intersect_fn(ray, hit) ? sets.hits : sets.misses;
    if (bucket.size() < kRays) bucket.push_back(ray);
  }
  return sets;
}

template <typename Intersect>
void run(benchmark::State& state, const std::vector<Ray>& rays, Intersect intersect_fn) {
  if (rays.empty()) {
    state.SkipWithError("no rays of this kind");
    return;
  }
  std::size_t i = 0;
  int found = 0;
  for (auto _ : state) {
    HitRecord hit;
    found += intersect_fn(rays[i], hit) ? 1 : 0;
    benchmark::DoNotOptimize(hit);
    i = (i + 1) % rays.size();
  }
  benchmark::DoNotOptimize(found);
  state.SetItemsProcessed(state.iterations());
}

// Registers "<name>/hit" and "<name>/miss" for one shape and intersect function.
template <typename Intersect>
void register_shape(const std::string& name, const dvec3& center, double radius,
                    Intersect intersect_fn) {
  const auto sets = std::make_shared<RaySets>(
      make_rays(center, radius, intersect_fn, std::hash<std::string>{}(name)));
  benchmark::RegisterBenchmark((name + "/hit").c_str(), [sets, intersect_fn](benchmark::State& s) {
    run(s, sets->hits, intersect_fn);
  });
  benchmark::RegisterBenchmark((name + "/miss").c_str(), [sets, intersect_fn](benchmark::State& s) {
    run(s, sets->misses, intersect_fn);
  });
}

template <typename Shape>
auto closest_hit(const Shape& shape) {
  return
      [shape](const Ray& ray, HitRecord& hit) { return intersect(shape, ray, kInfinity, hit, 0u); };
}

void register_intersectors() {
  const Sphere sphere{vec3(0.0f), 1.0f, 0};
  register_shape("sphere", dvec3(0.0), 1.0, closest_hit(sphere));
  register_shape("plane", dvec3(0.0), 1.0,
                 closest_hit(Plane::make(vec3(0.0f), vec3(0.3f, 1.0f, 0.2f), 0)));
  register_shape("disk", dvec3(0.0), 1.0,
                 closest_hit(Disk::make(vec3(0.0f), vec3(0.3f, 1.0f, 0.2f), 1.0f, 0)));
  register_shape("quad", dvec3(0.0), 1.0,
                 closest_hit(Quad::make(vec3(-0.7f, -0.7f, 0.0f), vec3(1.4f, 0.0f, 0.3f),
                                        vec3(0.0f, 1.4f, 0.0f), 0)));
  const Triangle triangle{vec3(-1.0f, -0.8f, 0.1f), vec3(1.0f, -0.6f, 0.0f),
                          vec3(0.0f, 1.0f, -0.1f), 0};
  register_shape("triangle (float Woop)", dvec3(0.0), 1.0, closest_hit(triangle));
  register_shape("triangle (double Woop)", dvec3(0.0), 1.0,
                 [triangle](const Ray& ray, HitRecord& hit) {
                   return intersect_precise(triangle, ray, kInfinity, hit, 0u);
                 });
  register_shape("cylinder (capped)", dvec3(0.0), 1.12,
                 closest_hit(Cylinder::make(vec3(0.0f, -1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0.5f,
                                            2.0f, true, 0)));
  register_shape("cone (capped)", dvec3(0.0), 1.12,
                 closest_hit(Cone::make(vec3(0.0f, -1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0.5f, 0.0f,
                                        2.0f, true, 0)));
  const Torus torus = Torus::make(vec3(0.0f), vec3(0.2f, 1.0f, 0.1f), 0.8f, 0.2f, 0);
  register_shape("torus (isolation)", dvec3(0.0), 1.0, closest_hit(torus));
  register_shape("torus (Algorithm 1010)", dvec3(0.0), 1.0,
                 [torus](const Ray& ray, HitRecord& hit) {
                   return detail::torus_candidates<detail::QuarticMethod::kAlgorithm1010>(
                              torus, make_precise_ray(ray), kInfinity, true)
                       .closest(ray.t_min, kInfinity, hit, 0u);
                 });
  const Torus thin = Torus::make(vec3(0.0f), vec3(0.2f, 1.0f, 0.1f), 1.0f, 1e-3f, 0);
  register_shape("torus r/R=1e-3 (isolation)", dvec3(0.0), 1.0, closest_hit(thin));
  Instance<Sphere> instanced_sphere;
  Instance<Sphere>::make(
      sphere,
      AffineTransform::from_trs(dvec3(5.0, 0.0, 0.0), dvec3(1, 1, 0), 0.7, dvec3(1, 2, 0.5)),
      instanced_sphere);
  register_shape("instance(sphere)", dvec3(5.0, 0.0, 0.0), 2.0, closest_hit(instanced_sphere));
  Instance<Torus> instanced_torus;
  Instance<Torus>::make(
      torus, AffineTransform::from_trs(dvec3(5.0, 0.0, 0.0), dvec3(1, 1, 0), 0.7, dvec3(1, 2, 0.5)),
      instanced_torus);
  register_shape("instance(torus)", dvec3(5.0, 0.0, 0.0), 2.0, closest_hit(instanced_torus));
  register_shape("sdf box (sphere traced)", dvec3(0.0), 1.0,
                 closest_hit(SdfBox{vec3(0.0f), vec3(0.6f, 0.5f, 0.4f), 0.0f, 0}));
  register_shape("sdf rounded box (sphere traced)", dvec3(0.0), 1.0,
                 closest_hit(SdfBox{vec3(0.0f), vec3(0.6f, 0.5f, 0.4f), 0.1f, 0}));
  register_shape("sdf torus (sphere traced)", dvec3(0.0), 1.0,
                 closest_hit(SdfTorus{vec3(0.0f), vec3(0.2f, 1.0f, 0.1f), 0.8f, 0.2f, 0}));
  register_shape("sdf capsule (sphere traced)", dvec3(0.0), 1.0,
                 closest_hit(SdfCapsule{vec3(0.0f, -0.5f, 0.0f), vec3(0.0f, 0.5f, 0.0f), 0.3f, 0}));
  // intersect_all on the torus (up to 4 sorted hits)
  register_shape("torus intersect_all", dvec3(0.0), 1.0, [torus](const Ray& ray, HitRecord& hit) {
    HitRecord hits[4];
    const int n = intersect_all(torus, ray, kInfinity, hits, 4, 0u);
    if (n > 0) hit = hits[0];
    return n > 0;
  });
}

// Patches and trimmed faces. The pools live as long as the program (the benchmarks hold
// plain pointers into them, as the renderer will).
SplinePatchDescription wavy_patch_description() {
  SplinePatchDescription d;
  d.count_u = d.count_v = 6;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      d.control_points.push_back(
          dvec3((i - 2.5) * 0.4, (j - 2.5) * 0.4, 0.3 * std::sin(1.7 * i + 2.3 * j)));
  for (int i = 0; i < 10; ++i) {
    d.knots_u.push_back(i);
    d.knots_v.push_back(i);
  }
  return d;
}

SplinePatchDescription sphere_octant_description() {
  const double w = std::sqrt(0.5);
  // Degree-elevated rational quarter circles (weights 1, 1/sqrt 2, 1).
  const glm::dvec4 h[3] = {glm::dvec4(1, 0, 0, 1), glm::dvec4(w, 0, w, w), glm::dvec4(0, 0, 1, 1)};
  const glm::dvec4 profile[4] = {h[0], (h[0] + 2.0 * h[1]) / 3.0, (2.0 * h[1] + h[2]) / 3.0, h[2]};
  const glm::dvec4 t[3] = {glm::dvec4(1, 0, 0, 1), glm::dvec4(w, w, 0, w), glm::dvec4(0, 1, 0, 1)};
  const glm::dvec4 turn[4] = {t[0], (t[0] + 2.0 * t[1]) / 3.0, (2.0 * t[1] + t[2]) / 3.0, t[2]};
  SplinePatchDescription d;
  d.count_u = d.count_v = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const dvec3 p = dvec3(profile[i]) / profile[i].w, r = dvec3(turn[j]) / turn[j].w;
      d.control_points.push_back(dvec3(p.x * r.x, p.x * r.y, p.z));
      d.weights.push_back(profile[i].w * turn[j].w);
    }
  d.knots_u = d.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  return d;
}

void register_patches() {
  static SplinePatchPool pool;
  static TrimPool trims;
  pool.pieces.reserve(16);  // no reallocation: the patches point into it
  SplinePatch wavy{}, octant{};
  build_spline_patch(wavy_patch_description(), pool, wavy);
  build_spline_patch(sphere_octant_description(), pool, octant);
  bind_pieces(wavy, pool.pieces.data());
  bind_pieces(octant, pool.pieces.data());
  register_shape("bspline patch (6x6, 9 pieces)", dvec3(0.0), 1.5, closest_hit(wavy));
  register_shape("nurbs patch (sphere octant)", dvec3(0.5), 1.0, closest_hit(octant));
  register_shape("bspline patch intersect_all", dvec3(0.0), 1.5,
                 [wavy](const Ray& ray, HitRecord& hit) {
                   HitRecord hits[16];
                   const int n = intersect_all(wavy, ray, kInfinity, hits, 16, 0u);
                   if (n > 0) hit = hits[0];
                   return n > 0;
                 });
  trims.points.reserve(64);
  trims.loops.reserve(8);
  Trimmed<SplinePatch> trimmed_patch{};
  build_trimmed_face(
      wavy,
      {{{3.0, 3.0}, {6.0, 3.0}, {6.0, 6.0}, {4.7, 6.0}, {4.5, 4.4}, {4.2, 6.0}, {3.0, 6.0}},
       {{3.5, 3.5}, {4.1, 3.6}, {3.8, 4.2}}},
      trims, trimmed_patch);
  Trimmed<Sphere> trimmed_sphere{};
  build_trimmed_face(Sphere{vec3(0.0f), 1.0f, 0},
                     {{{0, 0.2}, {0.5, 0.2}, {1, 0.2}, {1, 0.8}, {0.5, 0.8}, {0, 0.8}},
                      {{0.93, 0.35}, {0.07, 0.4}, {0.05, 0.65}, {0.9, 0.6}}},
                     trims, trimmed_sphere);
  bind_trim_region(trimmed_patch.region, trims);
  bind_trim_region(trimmed_sphere.region, trims);
  register_shape("trimmed face (bspline patch, hole)", dvec3(0.0), 1.5, closest_hit(trimmed_patch));
  register_shape("trimmed face (sphere, seam hole)", dvec3(0.0), 1.0, closest_hit(trimmed_sphere));
  // The trim test alone: uv points spread over the patch domain, inside and outside.
  const auto points = std::make_shared<std::vector<dvec2>>();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(2.9, 6.1);
  for (int k = 0; k < kRays; ++k) points->push_back(dvec2(u(rng), u(rng)));
  const TrimRegion region = trimmed_patch.region;
  benchmark::RegisterBenchmark("trim test alone (7 + 3 point loops)",
                               [points, region](benchmark::State& state) {
                                 std::size_t i = 0;
                                 int inside = 0;
                                 for (auto _ : state) {
                                   inside += face_contains(region, (*points)[i]) ? 1 : 0;
                                   i = (i + 1) % points->size();
                                 }
                                 benchmark::DoNotOptimize(inside);
                                 state.SetItemsProcessed(state.iterations());
                               });
}

// The quartic solvers on random quartics with four real roots in [-1, 1].
std::vector<Polynomial<4, double>> random_quartics(int count, bool four_real) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Polynomial<4, double>> out;
  for (int k = 0; k < count; ++k) {
    const double a = u(rng), b = u(rng), c = u(rng), d = four_real ? u(rng) : 0.0;
    // (x - a)(x - b) times (x - c)(x - d) or (x^2 + c x + 1 + |d|) (complex pair)
    const double p1 = -(a + b), p0 = a * b;
    const double q1 = four_real ? -(c + d) : c, q0 = four_real ? c * d : 1.0 + std::fabs(c);
    out.push_back(
        Polynomial<4, double>{{p0 * q0, p1 * q0 + p0 * q1, q0 + p1 * q1 + p0, q1 + p1, 1.0}});
  }
  return out;
}

void register_solvers() {
  for (const bool four_real : {true, false}) {
    const auto polys =
        std::make_shared<std::vector<Polynomial<4, double>>>(random_quartics(kRays, four_real));
    const std::string kind = four_real ? "/4 real roots" : "/2 real roots";
    benchmark::RegisterBenchmark(
        ("quartic isolation on [-2,2]" + kind).c_str(), [polys](benchmark::State& s) {
          std::size_t i = 0;
          for (auto _ : s) {
            double roots[4];
            benchmark::DoNotOptimize(roots_in_interval((*polys)[i], -2.0, 2.0, roots));
            benchmark::DoNotOptimize(roots);
            i = (i + 1) % polys->size();
          }
          s.SetItemsProcessed(s.iterations());
        });
    benchmark::RegisterBenchmark(
        ("quartic Algorithm 1010" + kind).c_str(), [polys](benchmark::State& s) {
          std::size_t i = 0;
          for (auto _ : s) {
            const auto& p = (*polys)[i];
            double roots[4];
            benchmark::DoNotOptimize(solve_quartic(p.c[4], p.c[3], p.c[2], p.c[1], p.c[0], roots));
            benchmark::DoNotOptimize(roots);
            i = (i + 1) % polys->size();
          }
          s.SetItemsProcessed(s.iterations());
        });
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_intersectors();
  register_patches();
  register_solvers();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
