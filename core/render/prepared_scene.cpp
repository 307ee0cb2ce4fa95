#include "tessera/render/prepared_scene.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

namespace tessera {

namespace {

vec3 to_float(const glm::dvec3& v) {
  return vec3(v);
}

// Normal-incidence colours of RayON's metal presets.
vec3 metal_preset_color(const std::string& preset, const vec3& fallback) {
  if (preset == "silver") return vec3(0.97f, 0.96f, 0.91f);
  if (preset == "gold") return vec3(1.00f, 0.78f, 0.34f);
  if (preset == "copper") return vec3(0.95f, 0.64f, 0.54f);
  if (preset == "aluminium" || preset == "aluminum") return vec3(0.91f, 0.92f, 0.92f);
  return fallback;
}

}  // namespace

Material make_material(const MaterialDesc& desc) {
  Material m;
  m.albedo = to_float(desc.albedo);
  m.emission = to_float(desc.emission);
  m.roughness = static_cast<float>(desc.roughness);
  m.ior = static_cast<float>(desc.refractive_index);
  switch (desc.type) {
    case MaterialType::kLambertian:
      m.kind = BsdfKind::kDiffuse;
      break;
    case MaterialType::kLight:
      m.kind = BsdfKind::kEmitter;
      break;
    case MaterialType::kMetal:
    case MaterialType::kRoughMirror:
      m.kind = BsdfKind::kConductor;
      break;
    case MaterialType::kAnisotropicMetal:
      // Anisotropy is approximated as isotropic roughness for now.
      m.kind = BsdfKind::kConductor;
      m.albedo = metal_preset_color(desc.preset, m.albedo);
      break;
    case MaterialType::kGlass:
      m.kind = BsdfKind::kDielectric;
      break;
    case MaterialType::kThinFilm:
      // Interference colours are not modelled: a thin shell with the film's Fresnel term.
      m.kind = BsdfKind::kThinDielectric;
      m.ior = static_cast<float>(desc.film_ior);
      break;
    case MaterialType::kClearCoat:
      m.kind = BsdfKind::kCoated;
      break;
  }
  // Transmissive surfaces stay faintly visible in the transparency view.
  const bool transmissive = m.kind == BsdfKind::kDielectric || m.kind == BsdfKind::kThinDielectric;
  m.opacity = static_cast<float>(transmissive ? std::max(0.1, 1.0 - desc.transmission)
                                              : 1.0 - desc.transmission);
  return m;
}

std::shared_ptr<const PreparedScene> PreparedScene::build(const SceneDescription& description,
                                                          const PrepareOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::shared_ptr<PreparedScene> scene(new PreparedScene());
  scene->settings_ = description.render;
  scene->features_ = SceneFeatures::of(description);

  for (const auto& m : description.materials) scene->materials_.push_back(make_material(m));
  // A scene with no materials still needs one for shapes to refer to.
  if (scene->materials_.empty()) scene->materials_.push_back(Material{});

  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> references;
  const auto add = [&](PrimitiveType type, std::uint32_t index, const Aabb& box, bool visible,
                       std::uint32_t material, float area) {
    const std::uint32_t ref = make_primitive_ref(type, index);
    if (visible) {
      boxes.push_back(box);
      references.push_back(ref);
    }
    if (scene->materials_[material].emissive() && area > 0.0f)
      scene->lights_.push_back(LightSource{ref, area});
  };

  for (const auto& s : description.spheres) {
    const Sphere sphere{to_float(s.center), static_cast<float>(s.radius), s.material};
    const auto index = static_cast<std::uint32_t>(scene->spheres_.size());
    scene->spheres_.push_back(sphere);
    add(PrimitiveType::kSphere, index, tessera::bounds(sphere), s.visible, s.material,
        surface_area(sphere));
  }
  for (const auto& q : description.quads) {
    const Quad quad = Quad::make(to_float(q.corner), to_float(q.u), to_float(q.v), q.material);
    const auto index = static_cast<std::uint32_t>(scene->quads_.size());
    scene->quads_.push_back(quad);
    add(PrimitiveType::kQuad, index, tessera::bounds(quad), q.visible, q.material,
        surface_area(quad));
  }
  for (const auto& mesh : description.meshes) {
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const Triangle tri{to_float(mesh.positions[mesh.indices[i]]),
                         to_float(mesh.positions[mesh.indices[i + 1]]),
                         to_float(mesh.positions[mesh.indices[i + 2]]), mesh.material};
      const auto index = static_cast<std::uint32_t>(scene->triangles_.size());
      scene->triangles_.push_back(tri);
      add(PrimitiveType::kTriangle, index, tessera::bounds(tri), mesh.visible, mesh.material,
          surface_area(tri));
    }
  }

  // Visible triangles are traced on the CPU by the SIMD structure (accel/triangle_accel.hpp),
  // every other shape by the BVH; BvhView::triangles joins the two for BvhTracer.
  std::vector<Triangle> visible_triangles;
  std::vector<std::uint32_t> triangle_references;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < references.size(); ++i) {
    if (primitive_type(references[i]) == PrimitiveType::kTriangle) {
      visible_triangles.push_back(scene->triangles_[primitive_index(references[i])]);
      triangle_references.push_back(references[i]);
    } else {
      boxes[kept] = boxes[i];
      references[kept++] = references[i];
    }
  }
  boxes.resize(kept);
  references.resize(kept);
  if (!visible_triangles.empty())
    scene->triangle_accel_ =
        TriangleAccel::build(visible_triangles, AccelBuildOptions{}, triangle_references);
  scene->bvh_ = build_bvh(boxes, references);
  scene->camera_ = Camera::from_description(description.camera, description.render.width,
                                            description.render.height);
  scene->background_ = to_float(description.background.color * description.background.intensity);
  scene->features_.light_count = static_cast<std::uint32_t>(scene->lights_.size());
  const auto& f = scene->features_;
  const bool path = description.render.integrator == IntegratorKind::kPath;
  scene->required_ = PipelineFeatures{f.shapes, path && f.light_count > 0, path && f.specular(),
                                      path && f.aovs != 0};
  scene->variant_ = options.all_features
                        ? &all_features_variant(description.render.integrator)
                        : &select_render_variant(description.render.integrator, scene->required_);
  scene->build_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::debug(
      "prepared scene: {}, integrator {}, variant shapes={:#x} lights={} specular={} aovs={}, BVH "
      "{} "
      "nodes depth {}, {:.3f} s",
      f.summary(), to_string(description.render.integrator), scene->variant_->features.shapes,
      scene->variant_->features.direct_lighting, scene->variant_->features.specular,
      scene->variant_->features.aovs, scene->bvh_.nodes.size(), scene->bvh_.depth,
      scene->build_seconds_);
  return scene;
}

SceneView PreparedScene::view() const {
  SceneView v;
  v.spheres = spheres_.data();
  v.quads = quads_.data();
  v.triangles = triangles_.data();
  v.materials = materials_.data();
  v.lights = lights_.data();
  v.light_count = static_cast<std::uint32_t>(lights_.size());
  v.bvh = bvh_.view();
  if (triangle_accel_.stats().triangles > 0) v.bvh.triangles = &triangle_accel_;
  v.camera = camera_;
  v.background = background_;
  return v;
}

TileStats PreparedScene::render_tile(const TileRect& tile, std::span<float> rgba) const {
  std::fill(rgba.begin(), rgba.end(), 0.0f);
  FilmPlanes film;
  film.beauty = rgba.data();
  // AOV-enabled variants write only the planes that are present, so none are passed here.
  const TileStats stats = variant_->render(view(), settings_, tile, film);
  for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
  return stats;
}

TileStats PreparedScene::render_tile(const TileRect& tile, TilePasses& passes) const {
  const std::size_t floats = tile.pixel_count() * 4;
  passes.beauty.assign(floats, 0.0f);
  FilmPlanes film;
  film.beauty = passes.beauty.data();
  float** planes[] = {&film.albedo, &film.normal, &film.depth, &film.primitive_id};
  for (std::size_t i = 0; i < passes.aovs.size(); ++i) {
    if ((settings_.aovs & (1u << i)) == 0) {
      passes.aovs[i].clear();
      continue;
    }
    passes.aovs[i].assign(floats, 0.0f);
    *planes[i] = passes.aovs[i].data();
  }
  const TileStats stats = variant_->render(view(), settings_, tile, film);
  const auto set_alpha = [](std::vector<float>& plane) {
    for (std::size_t i = 3; i < plane.size(); i += 4) plane[i] = 1.0f;
  };
  set_alpha(passes.beauty);
  for (auto& plane : passes.aovs) set_alpha(plane);
  return stats;
}

std::vector<float> render_image(const PreparedScene& scene) {
  const auto& s = scene.settings();
  std::vector<float> image(static_cast<std::size_t>(s.width) * s.height * 4, 0.0f);
  std::vector<float> tile_buffer;
  for (const TileRect& tile : make_tiles(s.width, s.height, s.tile_size)) {
    tile_buffer.resize(tile.pixel_count() * 4);
    scene.render_tile(tile, tile_buffer);
    for (std::uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(
          tile_buffer.begin() + static_cast<std::ptrdiff_t>(row) * tile.width * 4, tile.width * 4,
          image.begin() + (static_cast<std::ptrdiff_t>(tile.y + row) * s.width + tile.x) * 4);
  }
  return image;
}

}  // namespace tessera
