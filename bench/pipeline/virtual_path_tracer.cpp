#include "virtual_path_tracer.hpp"

#include <algorithm>
#include <cmath>

#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/math/offset_ray.hpp"
#include "tessera/math/rng.hpp"
#include "tessera/math/sampling.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/material_mapping.hpp"

namespace tessera::bench {

namespace {

class Shape {
 public:
  virtual ~Shape() = default;
  virtual bool intersect(const Ray& ray, float t_max, HitRecord& hit, std::uint32_t id) const = 0;
  virtual SurfaceInteraction surface(const Ray& ray, const HitRecord& hit) const = 0;
  virtual Aabb bounds() const = 0;
  virtual float area() const = 0;
  virtual void sample(float u1, float u2, vec3& point, vec3& normal) const = 0;
  virtual std::uint32_t material() const = 0;
};

template <typename T>
class ShapeOf final : public Shape {
 public:
  explicit ShapeOf(const T& shape) : shape_(shape) {}
  bool intersect(const Ray& ray, float t_max, HitRecord& hit, std::uint32_t id) const override {
    return tessera::intersect(shape_, ray, t_max, hit, id);
  }
  SurfaceInteraction surface(const Ray& ray, const HitRecord& hit) const override {
    return surface_at(shape_, ray, hit);
  }
  Aabb bounds() const override { return tessera::bounds(shape_); }
  float area() const override { return surface_area(shape_); }
  void sample(float u1, float u2, vec3& point, vec3& normal) const override {
    if constexpr (std::is_same_v<T, Sphere>) {
      normal = sample_uniform_sphere(u1, u2);
      point = shape_.center + shape_.radius * normal;
    } else if constexpr (std::is_same_v<T, Quad>) {
      point = shape_.corner + u1 * shape_.u + u2 * shape_.v;
      normal = shape_.normal;
    } else {
      const vec2 b = sample_uniform_triangle(u1, u2);
      point = b.x * shape_.p0 + b.y * shape_.p1 + (1.0f - b.x - b.y) * shape_.p2;
      normal = glm::normalize(glm::cross(shape_.p1 - shape_.p0, shape_.p2 - shape_.p0));
    }
  }
  std::uint32_t material() const override { return shape_.material; }

 private:
  T shape_;
};

struct ScatterResult {
  vec3 direction{0.0f};
  bool diffuse = false;
};

class BsdfBase {
 public:
  virtual ~BsdfBase() = default;
  // Chooses the continuation; may scale the throughput.
  virtual ScatterResult scatter(const SurfaceInteraction& si, const vec3& wo, SampleStream& rng,
                                vec3& throughput) const = 0;
};

class MaterialBsdf final : public BsdfBase {
 public:
  explicit MaterialBsdf(const Material& m) : m_(m) {}
  ScatterResult scatter(const SurfaceInteraction& si, const vec3& wo, SampleStream& rng,
                        vec3& throughput) const override {
    const vec3 n = si.geometric_normal;
    ScatterResult r;
    switch (m_.kind) {
      case BsdfKind::kDiffuse:
      case BsdfKind::kEmitter:
        r.diffuse = true;
        break;
      case BsdfKind::kCoated:
        if (rng.next() >= schlick_reflectance(-glm::dot(wo, n), 1.0f / m_.ior)) {
          r.diffuse = true;
        } else {
          r.direction = fuzzy_reflect(wo, n, m_.roughness, rng.next(), rng.next(), rng.next());
        }
        break;
      case BsdfKind::kConductor:
        r.direction = fuzzy_reflect(wo, n, m_.roughness, rng.next(), rng.next(), rng.next());
        throughput *= m_.albedo;
        break;
      case BsdfKind::kDielectric: {
        const float eta = si.front_face ? 1.0f / m_.ior : m_.ior;
        vec3 refracted;
        const bool can = refract(wo, n, eta, refracted);
        r.direction = (!can || rng.next() < schlick_reflectance(-glm::dot(wo, n), eta))
                          ? reflect(wo, n)
                          : refracted;
        throughput *= m_.albedo;
        break;
      }
      case BsdfKind::kThinDielectric: {
        const float f = schlick_reflectance(-glm::dot(wo, n), 1.0f / m_.ior);
        r.direction = rng.next() < 2.0f * f / (1.0f + f) ? reflect(wo, n) : wo;
        break;
      }
    }
    return r;
  }
  const Material& material() const { return m_; }

 private:
  Material m_;
};

}  // namespace

class VirtualScene {
 public:
  std::vector<std::unique_ptr<Shape>> shapes;
  std::vector<std::unique_ptr<MaterialBsdf>> materials;
  std::vector<const Shape*> lights;
  Bvh bvh;
  Camera camera{};
  vec3 background{0.0f};

  bool trace(const Ray& ray, HitRecord& hit, bool any_hit) const {
    hit.t = ray.t_max;
    const auto test = [this](std::uint32_t id, const Ray& r, float t_max, HitRecord& h) {
      return shapes[id]->intersect(r, t_max, h, id);
    };
    // The conventional code decides per ray, at run time, which query it runs.
    return any_hit ? traverse_bvh<true>(bvh.view(), ray, hit, test)
                   : traverse_bvh<false>(bvh.view(), ray, hit, test);
  }
};

VirtualPathTracer::VirtualPathTracer(const SceneDescription& d)
    : scene_(std::make_unique<VirtualScene>()) {
  settings_ = d.render;
  auto& s = *scene_;
  for (const auto& m : d.materials)
    s.materials.push_back(std::make_unique<MaterialBsdf>(make_material(m)));
  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> refs;
  const auto add = [&](std::unique_ptr<Shape> shape, bool visible) {
    const auto id = static_cast<std::uint32_t>(s.shapes.size());
    if (visible) {
      boxes.push_back(shape->bounds());
      refs.push_back(id);
    }
    if (s.materials[shape->material()]->material().emissive()) s.lights.push_back(shape.get());
    s.shapes.push_back(std::move(shape));
  };
  for (const auto& sp : d.spheres)
    add(std::make_unique<ShapeOf<Sphere>>(
            Sphere{vec3(sp.center), static_cast<float>(sp.radius), sp.material}),
        sp.visible);
  for (const auto& q : d.quads)
    add(std::make_unique<ShapeOf<Quad>>(
            Quad::make(vec3(q.corner), vec3(q.u), vec3(q.v), q.material)),
        q.visible);
  for (const auto& mesh : d.meshes)
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      add(std::make_unique<ShapeOf<Triangle>>(Triangle{
              vec3(mesh.positions[mesh.indices[i]]), vec3(mesh.positions[mesh.indices[i + 1]]),
              vec3(mesh.positions[mesh.indices[i + 2]]), mesh.material}),
          mesh.visible);
  s.bvh = build_bvh(boxes, refs);
  s.camera = Camera::from_description(d.camera, d.render.width, d.render.height);
  s.background = vec3(d.background.color * d.background.intensity);
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
        SampleStream rng(settings_.seed, x, y, sample);
        const float jx = rng.next(), jy = rng.next();
        Ray ray = s.camera.generate(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
        vec3 radiance(0.0f), throughput(1.0f);
        bool count_emission = true;
        ++stats.rays;
        for (std::uint32_t depth = 0;;) {
          HitRecord hit;
          if (!s.trace(ray, hit, false)) {
            radiance += throughput * s.background;
            break;
          }
          const Shape& shape = *s.shapes[hit.primitive];
          const SurfaceInteraction si = shape.surface(ray, hit);
          const MaterialBsdf& bsdf = *s.materials[si.material];
          const Material& m = bsdf.material();
          if (m.emissive() && count_emission) radiance += throughput * m.emission;
          if (m.kind == BsdfKind::kEmitter || depth + 1 >= settings_.max_depth) break;
          const vec3 n = si.geometric_normal;
          ScatterResult r = bsdf.scatter(si, ray.direction, rng, throughput);
          if (r.diffuse) {
            throughput *= m.albedo;
            if (!s.lights.empty()) {  // tested per hit at run time
              const float pick = rng.next() * static_cast<float>(s.lights.size());
              const Shape& light = *s.lights[std::min<std::size_t>(static_cast<std::size_t>(pick),
                                                                   s.lights.size() - 1)];
              vec3 point, light_normal;
              const float u1 = rng.next(), u2 = rng.next();
              light.sample(u1, u2, point, light_normal);
              const vec3 origin = offset_ray_origin(si.position, n);
              const vec3 to_light = point - origin;
              const float d2 = glm::dot(to_light, to_light);
              if (d2 > 0.0f) {
                const float d = std::sqrt(d2);
                const vec3 wi = to_light / d;
                const float cs = glm::dot(wi, n), cl = std::fabs(glm::dot(wi, light_normal));
                if (cs > 0.0f && cl > 0.0f) {
                  ++stats.rays;
                  HitRecord shadow;
                  if (!s.trace(Ray{origin, wi, 0.0f, d * (1.0f - 1e-4f)}, shadow, true)) {
                    const float pdf = 1.0f / (light.area() * static_cast<float>(s.lights.size()));
                    radiance += throughput * s.materials[light.material()]->material().emission *
                                (kInvPi * cs * cl / (d2 * pdf));
                  }
                }
              }
            }
            r.direction =
                Frame::from_normal(n).to_world(sample_cosine_hemisphere(rng.next(), rng.next()));
            count_emission = s.lights.empty();
          } else {
            count_emission = true;
          }
          if (r.direction == vec3(0.0f)) break;
          ++depth;
          if (depth >= 3) {
            const float survive = glm::clamp(max_component(throughput), 0.05f, 1.0f);
            if (rng.next() >= survive) break;
            throughput /= survive;
          }
          const vec3 side = glm::dot(r.direction, n) >= 0.0f ? n : -n;
          ray = Ray{offset_ray_origin(si.position, side), r.direction, 0.0f, kInfinity};
          ++stats.rays;
        }
        if (!(std::isfinite(radiance.x) && std::isfinite(radiance.y) && std::isfinite(radiance.z)))
          continue;
        float* pixel =
            &rgba[4 * ((static_cast<std::size_t>(y) - tile.y) * tile.width + (x - tile.x))];
        pixel[0] += radiance.x * weight;
        pixel[1] += radiance.y * weight;
        pixel[2] += radiance.z * weight;
      }
  for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
  return stats;
}

}  // namespace tessera::bench
