#include "virtual_path_tracer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/math/offset_ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/math/sampling.hpp"
#include "tessera/math/spherical_rectangle.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/light_sampling.hpp"
#include "tessera/render/light_tree.hpp"
#include "tessera/render/material_mapping.hpp"
#include "tessera/render/path_tracer.hpp"

namespace tessera::bench {

namespace {

// ---------------------------------------------------------------------------------------
// Shapes: intersection, surface and, for emitters, the light interface, all virtual.

class Shape {
 public:
  virtual ~Shape() = default;
  virtual bool intersect(const Ray& ray, float t_max, HitRecord& hit, std::uint32_t id) const = 0;
  virtual SurfaceInteraction surface(const Ray& ray, const HitRecord& hit) const = 0;
  virtual Aabb bounds() const = 0;
  virtual std::uint32_t material() const = 0;
  // As an emitter whose sampled area is `area`: a direction from `ref` towards it with its
  // solid-angle pdf and distance (not the radiance). False when it subtends nothing from ref.
  virtual bool sample_light(const vec3& ref, float area, float u1, float u2,
                            LightSample& out) const = 0;
  // The solid-angle pdf with which sample_light(ref) gives unit direction `wi`, whose ray
  // meets this shape at `distance` with geometric normal `light_normal`.
  virtual float light_pdf(const vec3& ref, float area, const vec3& wi, float distance,
                          const vec3& light_normal) const = 0;
};

template <typename T>
class ShapeOf : public Shape {
 public:
  explicit ShapeOf(const T& shape) : shape_(shape) {}
  bool intersect(const Ray& ray, float t_max, HitRecord& hit, std::uint32_t id) const override {
    return tessera::intersect(shape_, ray, t_max, hit, id);
  }
  SurfaceInteraction surface(const Ray& ray, const HitRecord& hit) const override {
    return surface_at(shape_, ray, hit);
  }
  Aabb bounds() const override { return tessera::bounds(shape_); }
  std::uint32_t material() const override { return shape_.material; }

 protected:
  T shape_;
};

// The light samplers are light_sampling.hpp's per-shape ones (sample_emitter,
// emitter_pdf), reached through a virtual call per shape class instead of a switch.
template <typename Shape>
class EmitterShape final : public ShapeOf<Shape> {
 public:
  using ShapeOf<Shape>::ShapeOf;

  bool sample_light(const vec3& ref, float area, float u1, float u2,
                    LightSample& out) const override {
    return sample_emitter(this->shape_, area, ref, u1, u2, out);
  }

  float light_pdf(const vec3& ref, float area, const vec3& wi, float distance,
                  const vec3& light_normal) const override {
    return emitter_pdf(this->shape_, area, ref, wi, distance, light_normal);
  }
};
using SphereShape = EmitterShape<Sphere>;
using QuadShape = EmitterShape<Quad>;
using TriangleShape = EmitterShape<Triangle>;

// ---------------------------------------------------------------------------------------
// BSDFs: one class per kind, sample/eval/pdf virtual, in the shading frame of bsdf.hpp
// (+z the shading normal on the arriving side). `front_face` says which side was hit; the
// classes that need it keep Bsdf::of's result for each side.

class BsdfModel {
 public:
  virtual ~BsdfModel() = default;
  virtual BsdfSample sample(const vec3& wo, bool front_face, float u_lobe, float u1,
                            float u2) const = 0;
  virtual vec3 eval(const vec3& wo, const vec3& wi, bool front_face) const = 0;
  virtual float pdf(const vec3& wo, const vec3& wi, bool front_face) const = 0;
  // True when eval and pdf can be non-zero somewhere, so light sampling can help.
  virtual bool has_non_specular() const = 0;
  // False when sample() ignores u_lobe, so the (lobe, light pick) pair is drawn only for
  // light sampling.
  virtual bool uses_lobe_sample() const = 0;
  // True when the lobe needs the surface's tangent (anisotropy_tangent, bsdf.hpp).
  virtual bool anisotropic() const { return false; }
  // True when eval and pdf can be non-zero below the surface (rough glass).
  virtual bool has_glossy_transmission() const { return false; }
};

class LambertianBsdf final : public BsdfModel {
 public:
  explicit LambertianBsdf(const vec3& albedo) : albedo_(albedo) {}
  BsdfSample sample(const vec3& wo, bool, float, float u1, float u2) const override {
    BsdfSample s;
    if (wo.z <= 0.0f) return s;
    s.wi = sample_cosine_hemisphere(u1, u2);
    if (s.wi.z <= 0.0f) return s;
    s.pdf = s.wi.z * kInvPi;
    s.f = albedo_ * kInvPi;
    s.lobe = kLobeReflection | kLobeDiffuse;
    return s;
  }
  vec3 eval(const vec3& wo, const vec3& wi, bool) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return vec3(0.0f);
    return albedo_ * kInvPi;
  }
  float pdf(const vec3& wo, const vec3& wi, bool) const override {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    return wi.z * kInvPi;
  }
  bool has_non_specular() const override { return true; }
  bool uses_lobe_sample() const override { return false; }

 private:
  vec3 albedo_;
};

// The GGX conductor: the same microfacet code as Bsdf (bsdf.hpp, microfacet.hpp), reached
// through this class's virtual calls.
class ConductorBsdf final : public BsdfModel {
 public:
  explicit ConductorBsdf(const Material& m) : ggx_(Bsdf::of(m, true)) {}
  BsdfSample sample(const vec3& wo, bool, float u_lobe, float u1, float u2) const override {
    return ggx_.sample(wo, u_lobe, u1, u2);
  }
  vec3 eval(const vec3& wo, const vec3& wi, bool) const override { return ggx_.eval(wo, wi); }
  float pdf(const vec3& wo, const vec3& wi, bool) const override { return ggx_.pdf(wo, wi); }
  bool has_non_specular() const override { return ggx_.has_non_specular(); }
  // The GGX lobe ignores u_lobe, but the specialised path tracer draws the pair for every
  // kind but diffuse: drawing it too keeps both on the same sample dimensions.
  bool uses_lobe_sample() const override { return true; }
  bool anisotropic() const override { return ggx_.anisotropic(); }

 private:
  Bsdf ggx_;
};

// A clear coat (exact Fresnel, GGX) over a Lambertian base: Bsdf's code (bsdf.hpp).
class CoatedBsdf final : public BsdfModel {
 public:
  explicit CoatedBsdf(const Material& m) : coated_(Bsdf::of(m, true)) {}
  BsdfSample sample(const vec3& wo, bool, float u_lobe, float u1, float u2) const override {
    return coated_.sample(wo, u_lobe, u1, u2);
  }
  vec3 eval(const vec3& wo, const vec3& wi, bool) const override { return coated_.eval(wo, wi); }
  float pdf(const vec3& wo, const vec3& wi, bool) const override { return coated_.pdf(wo, wi); }
  bool has_non_specular() const override { return true; }
  bool uses_lobe_sample() const override { return true; }

 private:
  Bsdf coated_;  // the coat faces air on both sides: the same whichever side is hit
};

// Glass, smooth or rough: Bsdf's code for the side that was hit (bsdf.hpp).
class DielectricBsdf final : public BsdfModel {
 public:
  explicit DielectricBsdf(const Material& m)
      : front_(Bsdf::of(m, true)), back_(Bsdf::of(m, false)) {}
  BsdfSample sample(const vec3& wo, bool front_face, float u_lobe, float u1,
                    float u2) const override {
    return side(front_face).sample(wo, u_lobe, u1, u2);
  }
  vec3 eval(const vec3& wo, const vec3& wi, bool front_face) const override {
    return side(front_face).eval(wo, wi);
  }
  float pdf(const vec3& wo, const vec3& wi, bool front_face) const override {
    return side(front_face).pdf(wo, wi);
  }
  bool has_non_specular() const override { return front_.has_non_specular(); }
  bool has_glossy_transmission() const override { return front_.has_glossy_transmission(); }
  bool uses_lobe_sample() const override { return true; }

 private:
  const Bsdf& side(bool front_face) const { return front_face ? front_ : back_; }
  Bsdf front_, back_;
};

// A thin film (Airy interference, reflection or straight through): Bsdf's code (bsdf.hpp,
// thin_film.hpp); the same on both faces.
class ThinDielectricBsdf final : public BsdfModel {
 public:
  explicit ThinDielectricBsdf(const Material& m) : film_(Bsdf::of(m, true)) {}
  BsdfSample sample(const vec3& wo, bool, float u_lobe, float u1, float u2) const override {
    return film_.sample(wo, u_lobe, u1, u2);
  }
  vec3 eval(const vec3&, const vec3&, bool) const override { return vec3(0.0f); }
  float pdf(const vec3&, const vec3&, bool) const override { return 0.0f; }
  bool has_non_specular() const override { return false; }
  bool uses_lobe_sample() const override { return true; }

 private:
  Bsdf film_;
};

// Null for emitters, which do not scatter.
std::unique_ptr<BsdfModel> make_bsdf(const Material& m) {
  switch (m.kind) {
    case BsdfKind::kDiffuse:
      return std::make_unique<LambertianBsdf>(m.albedo);
    case BsdfKind::kConductor:
      return std::make_unique<ConductorBsdf>(m);
    case BsdfKind::kCoated:
      return std::make_unique<CoatedBsdf>(m);
    case BsdfKind::kDielectric:
      return std::make_unique<DielectricBsdf>(m);
    case BsdfKind::kThinDielectric:
      return std::make_unique<ThinDielectricBsdf>(m);
    case BsdfKind::kEmitter:
    case BsdfKind::kConstant:  // unlit materials are not part of this baseline
    case BsdfKind::kShowNormals:
      break;
  }
  return nullptr;
}

struct VirtualMaterial {
  vec3 emission{0.0f};
  bool emissive = false;
  std::unique_ptr<BsdfModel> bsdf;  // null: an emitter
};

struct Light {
  const Shape* shape = nullptr;
  float area = 0.0f;
  float pmf = 0.0f;              // picked by power
  bool hit_by_rays = true;       // false: a delta light, found by light sampling alone
  std::uint32_t tree_depth = 0;  // its leaf in the light tree
  std::uint64_t tree_path = 0;
};

// The state PathPayload carries between vertices.
struct PathState {
  vec3 radiance{0.0f};
  vec3 throughput{1.0f};
  std::uint32_t depth = 0;
  std::uint32_t rays = 1;
  bool count_emission = true;
  float previous_pdf = 0.0f;
  vec3 previous_position{0.0f};
  vec3 previous_normal{0.0f};
};

}  // namespace

class VirtualScene {
 public:
  std::vector<std::unique_ptr<Shape>> shapes;
  std::vector<std::int32_t> light_of_shape;  // index into lights, -1 when not sampled
  std::vector<VirtualMaterial> materials;
  std::vector<Light> lights;
  std::vector<AliasSlot> light_alias;
  std::vector<LightTreeNode> light_tree;  // empty: lights are picked by power
  Bvh bvh;
  Camera camera{};
  vec3 background{0.0f};
  std::uint32_t max_depth = 1;
  LightStrategy strategy = LightStrategy::kMis;
  float spawn_scale = 1.0f;  // the pipeline's (SceneView::spawn_scale)

  // Two traversals: the conventional code decides per ray, at run time, which query it runs.
  bool trace(const Ray& ray, HitRecord& hit, bool any_hit) const {
    hit.t = ray.t_max;
    const auto test = [this](std::uint32_t id, const Ray& r, float t_max, HitRecord& h) {
      return shapes[id]->intersect(r, t_max, h, id);
    };
    return any_hit ? traverse_bvh<true>(bvh.view(), ray, hit, test)
                   : traverse_bvh<false>(bvh.view(), ray, hit, test);
  }
  bool closest(const Ray& ray, HitRecord& hit) const { return trace(ray, hit, false); }
  bool occluded(const Ray& ray) const {
    HitRecord hit;
    return trace(ray, hit, true);
  }

  LightPick pick_light(const vec3& p, const vec3& n, float u) const {
    if (!light_tree.empty()) {  // tested per pick at run time
      const TreePick t = light_tree_pick(light_tree.data(), p, n, u);
      return LightPick{t.light, t.pmf, t.u};
    }
    float rest = 0.0f;
    const std::uint32_t index =
        alias_pick(light_alias.data(), static_cast<std::uint32_t>(lights.size()), u, rest);
    return LightPick{index, lights[index].pmf, rest};
  }
  float pick_pmf(const vec3& p, const vec3& n, const Light& light) const {
    if (!light_tree.empty())
      return light_tree_pmf(light_tree.data(), p, n, light.tree_path, light.tree_depth);
    return light.pmf;
  }

  // Next-event estimation at `si` (estimate_direct): f cos Li / pdf for one light sample,
  // weighted against BSDF sampling as `strategy` says.
  vec3 estimate_direct(const SurfaceInteraction& si, const Frame& frame, const vec3& wo,
                       const BsdfModel& bsdf, const BounceSamples& u, std::uint32_t& rays) const {
    const LightPick pick = pick_light(si.position, si.geometric_normal,
                                      u.pick_with_light_point ? u.light_u1 : u.light_pick);
    if (!(pick.pmf > 0.0f)) return vec3(0.0f);
    const Light& light = lights[pick.index];
    if (strategy == LightStrategy::kBsdf && light.hit_by_rays) return vec3(0.0f);
    LightSample ls;
    const float light_u1 = u.pick_with_light_point ? pick.reused_u : u.light_u1;
    if (!light.shape->sample_light(si.position, light.area, light_u1, u.light_u2, ls))
      return vec3(0.0f);
    ls.radiance = materials[light.shape->material()].emission;
    const float side = glm::dot(ls.wi, si.geometric_normal);
    if (side <= 0.0f && !bsdf.has_glossy_transmission()) return vec3(0.0f);
    const vec3 wi = frame.to_local(ls.wi);
    if ((wi.z > 0.0f) != (side > 0.0f)) return vec3(0.0f);
    const vec3 f = bsdf.eval(wo, wi, si.front_face) * std::fabs(wi.z);
    if (!(f.x > 0.0f || f.y > 0.0f || f.z > 0.0f)) return vec3(0.0f);
    const float pdf = pick.pmf * ls.pdf;
    if (!(pdf > 0.0f)) return vec3(0.0f);
    ++rays;
    const vec3 origin =
        offset_ray_origin(si.position, side > 0.0f ? si.geometric_normal : -si.geometric_normal,
                          spawn_scale, si.position_error);
    const vec3 to_light = si.position + ls.distance * ls.wi - origin;
    const float length = glm::length(to_light);
    if (occluded(Ray{origin, to_light / length, 0.0f, length * (1.0f - 1e-4f)})) return vec3(0.0f);
    const float weight = strategy == LightStrategy::kMis && light.hit_by_rays
                             ? power_heuristic(pdf, bsdf.pdf(wo, wi, si.front_face))
                             : 1.0f;
    return f * ls.radiance * (weight / pdf);
  }

  // The share of an emitter's radiance a hit counts (PathHit::emission_weight).
  float emission_weight(const Ray& ray, const HitRecord& hit, const SurfaceInteraction& si,
                        const PathState& path) const {
    if (path.count_emission) return 1.0f;
    const std::int32_t index = light_of_shape[hit.primitive];
    if (index < 0) return 1.0f;  // no sampler: only hits find it
    switch (strategy) {
      case LightStrategy::kBsdf:
        return 1.0f;
      case LightStrategy::kLight:
        return 0.0f;
      case LightStrategy::kMis:
        break;
    }
    const Light& light = lights[static_cast<std::size_t>(index)];
    const float distance = glm::length(si.position - path.previous_position);
    const float pdf_light = pick_pmf(path.previous_position, path.previous_normal, light) *
                            light.shape->light_pdf(path.previous_position, light.area,
                                                   ray.direction, distance, si.geometric_normal);
    return power_heuristic(path.previous_pdf, pdf_light);
  }

  // One path vertex (PathHit::on_hit): emission, light sampling, the BSDF sample and
  // Russian roulette. Returns false when the path ends here, else sets `next`.
  bool shade(const Ray& ray, const HitRecord& hit, SampleStream& rng, PathState& path,
             Ray& next) const {
    const SurfaceInteraction si = shapes[hit.primitive]->surface(ray, hit);
    const VirtualMaterial& material = materials[si.material];
    if (material.emissive)
      path.radiance += path.throughput * material.emission * emission_weight(ray, hit, si, path);
    if (material.bsdf == nullptr) return false;  // an emitter
    if (path.depth + 1 >= max_depth) return false;
    const BsdfModel& bsdf = *material.bsdf;

    const vec3 ng = si.geometric_normal;
    const Frame frame = bsdf.anisotropic()
                            ? Frame::from_normal_and_tangent(si.shading_normal,
                                                             anisotropy_tangent(si.shading_normal))
                            : Frame::from_normal(si.shading_normal);
    const vec3 wo = frame.to_local(-ray.direction);
    BounceSamples u;
    const bool sample_lights = !lights.empty() && bsdf.has_non_specular();
    if (bsdf.uses_lobe_sample())
      BounceSamples::draw(rng, path.depth, BouncePair::kLobeAndPick, u.lobe, u.light_pick);
    else
      u.pick_with_light_point = true;
    if (sample_lights) {
      BounceSamples::draw(rng, path.depth, BouncePair::kLightPoint, u.light_u1, u.light_u2);
      path.radiance += path.throughput * estimate_direct(si, frame, wo, bsdf, u, path.rays);
    }
    BounceSamples::draw(rng, path.depth, BouncePair::kBsdfDirection, u.bsdf_u1, u.bsdf_u2);

    const BsdfSample bs = bsdf.sample(wo, si.front_face, u.lobe, u.bsdf_u1, u.bsdf_u2);
    if (!bs.valid()) return false;
    const vec3 direction = frame.to_world(bs.wi);
    const float side = glm::dot(direction, ng);
    if ((bs.lobe & kLobeReflection) != 0 ? side <= 0.0f : side >= 0.0f) return false;
    path.throughput *= bs.weight();
    path.previous_pdf = bs.pdf;
    path.previous_position = si.position;
    path.previous_normal = ng;
    path.count_emission = bs.specular() || lights.empty();

    ++path.depth;
    if (path.depth >= 3) {
      const float survive = roulette_survival(path.throughput);
      if (BounceSamples::roulette(rng, path.depth - 1) >= survive) return false;
      path.throughput /= survive;
    }
    const vec3 side_normal = side >= 0.0f ? ng : -ng;
    next = Ray{offset_ray_origin(si.position, side_normal, spawn_scale, si.position_error),
               direction, 0.0f, kInfinity};
    ++path.rays;
    return true;
  }
};

VirtualPathTracer::VirtualPathTracer(const SceneDescription& d, bool light_tree)
    : scene_(std::make_unique<VirtualScene>()) {
  settings_ = d.render;
  auto& s = *scene_;
  std::vector<Material> params;
  for (const auto& m : d.materials) params.push_back(make_material(m));
  if (params.empty()) params.push_back(Material{});  // as PreparedScene
  for (const Material& m : params)
    s.materials.push_back(VirtualMaterial{m.emission, m.emissive(), make_bsdf(m)});

  // Each shape is also keyed by the tagged reference the pipeline's build gives it (its
  // type and its index among that type), to find the emitters in its light list.
  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> refs;
  std::unordered_map<std::uint32_t, std::uint32_t> shape_of_reference;
  std::uint32_t count_of_type[3] = {0, 0, 0};
  const auto add = [&](std::unique_ptr<Shape> shape, bool visible, PrimitiveType type) {
    const auto id = static_cast<std::uint32_t>(s.shapes.size());
    // The pipeline hides such shapes from camera rays alone; this baseline has one tree.
    if (!visible)
      throw std::invalid_argument("virtual path tracer: a shape hidden from the camera");
    boxes.push_back(shape->bounds());
    refs.push_back(id);
    shape_of_reference[make_primitive_ref(type, count_of_type[static_cast<int>(type)]++)] = id;
    s.shapes.push_back(std::move(shape));
  };
  for (const auto& sp : d.spheres)
    add(std::make_unique<SphereShape>(
            Sphere{vec3(sp.center), static_cast<float>(sp.radius), sp.material}),
        sp.visible, PrimitiveType::kSphere);
  for (const auto& q : d.quads)
    add(std::make_unique<QuadShape>(Quad::make(vec3(q.corner), vec3(q.u), vec3(q.v), q.material)),
        q.visible, PrimitiveType::kQuad);
  for (const auto& mesh : d.meshes)
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      add(std::make_unique<TriangleShape>(Triangle{
              vec3(mesh.positions[mesh.indices[i]]), vec3(mesh.positions[mesh.indices[i + 1]]),
              vec3(mesh.positions[mesh.indices[i + 2]]), mesh.material}),
          mesh.visible, PrimitiveType::kTriangle);
  s.bvh = build_bvh(boxes, refs);
  s.camera = Camera::from_description(d.camera, d.render.width, d.render.height);
  s.background = vec3(d.background.color * d.background.intensity);
  s.max_depth = d.render.max_depth;
  s.strategy = d.render.light_strategy;

  // The light list, its alias table and its light tree are the pipeline's, taken from its
  // scene build, so both renderers pick from one list in one order (sorted by reference)
  // with the same probabilities. Meshes are baked (no shared geometry), so triangle
  // references count the triangles in description order, as above.
  const auto prepared =
      PreparedScene::build(d, PrepareOptions{.instancing = false, .light_tree = light_tree});
  const SceneView view = prepared->view();
  s.spawn_scale = view.spawn_scale;
  s.light_of_shape.assign(s.shapes.size(), -1);
  for (std::uint32_t i = 0; i < view.light_count; ++i) {
    const LightSource& l = view.lights[i];
    const auto found = shape_of_reference.find(l.primitive);
    if (found == shape_of_reference.end())
      throw std::invalid_argument(
          "virtual path tracer: an emitter it does not model (only untransformed spheres, quads "
          "and meshes)");
    s.lights.push_back(Light{s.shapes[found->second].get(), l.area, l.pmf, l.hit_by_rays,
                             l.tree_depth, l.tree_path});
    s.light_of_shape[found->second] = static_cast<std::int32_t>(i);
  }
  s.light_alias.assign(view.light_alias, view.light_alias + view.light_count);
  if (view.light_tree != nullptr) {
    // The nodes are stored depth first from the root: their count is one past the last
    // node reached.
    std::uint32_t end = 0;
    const auto walk = [&](const auto& self, std::uint32_t at) -> void {
      end = std::max(end, at + 1);
      for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) {
        const std::uint32_t child = view.light_tree[at].child[k];
        if (!LightTreeNode::is_leaf(child)) self(self, child);
      }
    };
    walk(walk, 0);
    s.light_tree.assign(view.light_tree, view.light_tree + end);
  }
}

VirtualPathTracer::~VirtualPathTracer() = default;

TileStats VirtualPathTracer::render_tile(const TileRect& tile, std::span<float> rgba) const {
  const VirtualScene& s = *scene_;
  TileStats stats;
  std::fill(rgba.begin(), rgba.end(), 0.0f);
  const float weight = 1.0f / static_cast<float>(settings_.samples_per_pixel);
  for (std::uint32_t y = tile.y; y < tile.y + tile.height; ++y)
    for (std::uint32_t x = tile.x; x < tile.x + tile.width; ++x)
      for (std::uint32_t sample = 0; sample < settings_.samples_per_pixel; ++sample) {
        SampleStream rng(settings_.seed, x, y, sample, settings_.sampler);
        float jx, jy;
        rng.next_2d(jx, jy);
        Ray ray = s.camera.generate(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
        PathState path;
        bool covered = false;  // the camera ray hit a surface: alpha is coverage
        for (;;) {
          HitRecord hit;
          const bool hit_something = s.closest(ray, hit);
          if (path.depth == 0) covered = hit_something;
          if (!hit_something) {
            path.radiance += path.throughput * s.background;
            break;
          }
          Ray next;
          if (!s.shade(ray, hit, rng, path, next)) break;
          ray = next;
        }
        stats.rays += path.rays;
        float* pixel =
            &rgba[4 * ((static_cast<std::size_t>(y) - tile.y) * tile.width + (x - tile.x))];
        if (covered) pixel[3] += weight;
        const vec3 l = path.radiance;
        if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) continue;
        pixel[0] += l.x * weight;
        pixel[1] += l.y * weight;
        pixel[2] += l.z * weight;
      }
  return stats;
}

}  // namespace tessera::bench
