#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/tile_accumulation.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "analytic_lights.hpp"
#include "mesh_sharing.hpp"
#include "mesh_triangles.hpp"
#include "pooled_surfaces.hpp"
#include "primitive_list.hpp"
#include "shape_placement.hpp"
#include "tessera/accel/shape_wide_bvh.hpp"
#include "tessera/math/offset_ray.hpp"
#include "tessera/render/accel_builder.hpp"
#include "tessera/render/material_mapping.hpp"
#include "texture_pool.hpp"
#include "variant_choice.hpp"

namespace tessera {

std::shared_ptr<const PreparedScene> PreparedScene::build(const SceneDescription& description,
                                                          const PrepareOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::shared_ptr<PreparedScene> scene(new PreparedScene());
  scene->settings_ = description.render;
  scene->features_ = SceneFeatures::of(description);

  for (const auto& m : description.materials) scene->materials_.push_back(make_material(m));
  // A scene with no materials still needs one for shapes to refer to.
  if (scene->materials_.empty()) scene->materials_.push_back(Material{});
  TexturePool textures = build_texture_pool(description.textures);
  scene->textures_ = std::move(textures.textures);
  scene->texels_ = std::move(textures.texels);
  bind_material_textures(description.materials, description.textures, scene->materials_);

  // Shapes go into their flat arrays in this order, each recorded for the acceleration
  // structures and the light list; the order decides both, and so the image.
  PrimitiveArrays& arrays = scene->arrays_;
  // Each displaced sphere shades with its own copy of its material carrying the dimples,
  // added before the primitive list takes its view of the materials.
  std::vector<std::uint32_t> dimpled_materials;
  for (const auto& d : description.displaced_spheres) {
    Material dimpled = scene->materials_[d.material];
    dimpled.golf_dimples = static_cast<float>(d.displacement_scale);
    dimpled_materials.push_back(static_cast<std::uint32_t>(scene->materials_.size()));
    scene->materials_.push_back(dimpled);
  }
  PrimitiveList primitives(scene->materials_, scene->lights_);
  for (const auto& s : description.spheres)
    place_curved(s, arrays.of<PrimitiveType::kSphere>(), PrimitiveType::kSphere,
                 arrays.of<PrimitiveType::kSphereInstance>(), PrimitiveType::kSphereInstance,
                 primitives);
  for (std::size_t i = 0; i < description.displaced_spheres.size(); ++i) {
    const DisplacedSphereDesc& d = description.displaced_spheres[i];
    const SphereDesc s{.center = d.center,
                       .radius = d.radius,
                       .material = dimpled_materials[i],
                       .visible = d.visible,
                       .source_index = d.source_index,
                       .transform = d.transform};
    place_curved(s, arrays.of<PrimitiveType::kSphere>(), PrimitiveType::kSphere,
                 arrays.of<PrimitiveType::kSphereInstance>(), PrimitiveType::kSphereInstance,
                 primitives);
  }
  // A parallelogram stays one under any affine map: quads are always baked.
  for (const auto& q : description.quads)
    primitives.store(arrays.of<PrimitiveType::kQuad>(), PrimitiveType::kQuad,
                     placed_surface(q, Placement(q.transform), q.material), q.visible, q.material);

  const bool attributes = stores_triangle_attributes(description.meshes);
  const SharedGeometryGroups groups = options.instancing
                                          ? shared_geometry_groups(description, scene->materials_)
                                          : SharedGeometryGroups{};
  std::vector<bool> shared(description.meshes.size(), false);
  for (const auto& group : groups)
    for (const std::size_t m : group) shared[m] = true;
  for (std::size_t m = 0; m < description.meshes.size(); ++m)
    if (!shared[m])
      bake_mesh(description.meshes[m], attributes, arrays.of<PrimitiveType::kTriangle>(),
                scene->triangle_attributes_, primitives);
  SharedMeshes shared_meshes = share_mesh_geometry(description, groups, attributes);
  scene->instanced_triangles_ = std::move(shared_meshes.triangles);
  scene->instanced_attributes_ = std::move(shared_meshes.attributes);
  // Moved, not copied: the top level points into the geometries' buffer, which a move keeps.
  scene->shared_meshes_ = std::move(shared_meshes.geometries);
  scene->mesh_placements_ = std::move(shared_meshes.placements);
  scene->instance_accel_ = std::move(shared_meshes.top_level);

  // Visible planes first: camera rays test all but the last hidden_plane_count.
  for (const bool visible : {true, false})
    for (const auto& p : description.planes)
      if (p.visible == visible)
        arrays.of<PrimitiveType::kPlane>().push_back(
            placed_surface(p, Placement(p.transform), p.material));
  scene->hidden_plane_count_ =
      static_cast<std::uint32_t>(std::count_if(description.planes.begin(), description.planes.end(),
                                               [](const auto& p) { return !p.visible; }));
  for (const auto& d : description.disks)
    place_curved(d, arrays.of<PrimitiveType::kDisk>(), PrimitiveType::kDisk,
                 arrays.of<PrimitiveType::kDiskInstance>(), PrimitiveType::kDiskInstance,
                 primitives);
  for (const auto& c : description.cylinders)
    place_curved(c, arrays.of<PrimitiveType::kCylinder>(), PrimitiveType::kCylinder,
                 arrays.of<PrimitiveType::kCylinderInstance>(), PrimitiveType::kCylinderInstance,
                 primitives);
  for (const auto& c : description.cones)
    place_curved(c, arrays.of<PrimitiveType::kCone>(), PrimitiveType::kCone,
                 arrays.of<PrimitiveType::kConeInstance>(), PrimitiveType::kConeInstance,
                 primitives);
  for (const auto& t : description.tori)
    place_curved(t, arrays.of<PrimitiveType::kTorus>(), PrimitiveType::kTorus,
                 arrays.of<PrimitiveType::kTorusInstance>(), PrimitiveType::kTorusInstance,
                 primitives);
  for (const auto& b : description.sdf_boxes)
    place_sdf(b, arrays.of<PrimitiveType::kSdfBox>(), PrimitiveType::kSdfBox,
              arrays.of<PrimitiveType::kSdfBoxInstance>(), PrimitiveType::kSdfBoxInstance,
              primitives);
  for (const auto& t : description.sdf_tori)
    place_sdf(t, arrays.of<PrimitiveType::kSdfTorus>(), PrimitiveType::kSdfTorus,
              arrays.of<PrimitiveType::kSdfTorusInstance>(), PrimitiveType::kSdfTorusInstance,
              primitives);
  for (const auto& c : description.sdf_capsules)
    place_sdf(c, arrays.of<PrimitiveType::kSdfCapsule>(), PrimitiveType::kSdfCapsule,
              arrays.of<PrimitiveType::kSdfCapsuleInstance>(), PrimitiveType::kSdfCapsuleInstance,
              primitives);

  PooledSurfaceArrays pooled{scene->patch_pool_,
                             scene->trim_pool_,
                             arrays.of<PrimitiveType::kSplinePatch>(),
                             arrays.of<PrimitiveType::kTrimmedPlane>(),
                             arrays.of<PrimitiveType::kTrimmedDisk>(),
                             arrays.of<PrimitiveType::kTrimmedQuad>(),
                             arrays.of<PrimitiveType::kTrimmedSphere>(),
                             arrays.of<PrimitiveType::kTrimmedCylinder>(),
                             arrays.of<PrimitiveType::kTrimmedCone>(),
                             arrays.of<PrimitiveType::kTrimmedTorus>(),
                             arrays.of<PrimitiveType::kTrimmedPatch>()};
  for (const auto& p : description.patches) place_patch(p, pooled, primitives);
  for (const auto& f : description.trimmed_faces) place_trimmed_face(f, pooled, primitives);
  bind_pools(pooled);

  const Aabb scene_bounds = primitives.bounds();
  if (!scene_bounds.empty())
    scene->spawn_scale_ = spawn_scale_for_extent(
        max_component(glm::max(glm::abs(scene_bounds.lower), glm::abs(scene_bounds.upper))));
  scene->simd_triangle_references_ = primitives.build_accelerators(
      arrays.of<PrimitiveType::kTriangle>(), accel_build_options(description.render.accel_builder),
      scene->triangle_accel_, scene->bvh_, scene->hidden_bvh_);
#if TESSERA_SHAPE_WIDE_WALK
  scene->shape_wide_bvh_ = collapse_shape_bvh(scene->bvh_);
#endif
  scene->camera_ = Camera::from_description(description.camera, description.render);
  AnalyticLightSet analytic = make_analytic_lights(description);
  scene->environment_ = analytic.environment;
  // Moved, the tables keep the addresses environment_ holds.
  scene->environment_pixels_ = std::move(analytic.environment_tables.pixels);
  scene->environment_marginal_ = std::move(analytic.environment_tables.marginal_cdf);
  scene->environment_conditional_ = std::move(analytic.environment_tables.conditional_cdf);
  // The preview integrators show one colour on a miss: the environment's average.
  scene->background_ = analytic.environment.average_radiance();
  scene->analytic_lights_ = std::move(analytic.lights);
  scene->first_analytic_light_ = static_cast<std::uint32_t>(scene->lights_.size());
  scene->first_infinite_light_ = scene->first_analytic_light_ + analytic.first_infinite;
  add_analytic_lights(scene->lights_, scene->analytic_lights_);
  const bool has_environment = !scene->environment_.black();
  scene->environment_light_ =
      static_cast<std::uint32_t>(scene->lights_.size()) - (has_environment ? 1u : 0u);
  const float scene_radius = lit_region_radius(
      scene->lights_, scene->view(), vec3(description.camera.position),
      scene_bounds.empty()
          ? 1.0f
          : glm::max(1e-3f, 0.5f * glm::length(scene_bounds.upper - scene_bounds.lower)));
  scene->light_alias_ =
      finish_light_list(scene->lights_, scene->materials_, scene->view(), scene_radius);
  for (std::uint32_t i = 0; i < scene->lights_.size(); ++i)
    if (scene->lights_[i].every_vertex)
      scene->every_vertex_lights_[scene->every_vertex_count_++] = i;
  if (options.light_tree && scene->first_infinite_light_ >= 2) {
    scene->light_tree_ = build_light_tree(scene->lights_, scene->materials_, scene->view());
    if (scene->first_infinite_light_ < scene->lights_.size())
      scene->infinite_pick_ =
          infinite_light_share(scene->lights_, scene->materials_, scene->view(), scene_radius);
  }
  scene->features_.light_count = static_cast<std::uint32_t>(scene->lights_.size());
  const auto& f = scene->features_;
  scene->required_ = required_pipeline_features(f, description.render.integrator);
  scene->variant_ =
      &choose_render_variant(description.render.integrator, scene->required_, options.all_features);
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
  arrays_.bind(v);
  v.triangle_attributes = triangle_attributes_.empty() ? nullptr : triangle_attributes_.data();
  v.materials = materials_.data();
  v.thin_films = std::any_of(materials_.begin(), materials_.end(),
                             [](const Material& m) { return m.kind == BsdfKind::kThinDielectric; });
  v.textures = textures_.data();
  v.texels = texels_.data();
  v.lights = lights_.data();
  v.light_alias = light_alias_.data();
  v.light_tree = light_tree_.empty() ? nullptr : light_tree_.data();
  v.light_count = static_cast<std::uint32_t>(lights_.size());
  v.bvh = bvh_.view();
  if (!shape_wide_bvh_.nodes.empty()) v.bvh.wide_nodes = shape_wide_bvh_.nodes.data();
  if (triangle_accel_.stats().triangles > 0) v.bvh.triangles = &triangle_accel_;
  v.instanced_triangles = instanced_triangles_.data();
  v.instanced_attributes = instanced_attributes_.empty() ? nullptr : instanced_attributes_.data();
  v.mesh_placements = mesh_placements_.data();
  v.mesh_placement_count = static_cast<std::uint32_t>(mesh_placements_.size());
  if (!mesh_placements_.empty()) v.bvh.instances = &instance_accel_;
  v.bvh.hidden_nodes = hidden_bvh_.nodes.data();
  v.bvh.hidden_primitives = hidden_bvh_.primitives.data();
  v.bvh.hidden_node_count = static_cast<std::uint32_t>(hidden_bvh_.nodes.size());
  v.hidden_plane_count = hidden_plane_count_;
  v.camera = camera_;
  v.background = background_;
  v.analytic_lights = analytic_lights_.data();
  v.analytic_light_count = static_cast<std::uint32_t>(analytic_lights_.size());
  v.first_analytic_light = first_analytic_light_;
  v.first_infinite_light = first_infinite_light_;
  v.infinite_pick = infinite_pick_;
  for (std::uint32_t i = 0; i < every_vertex_count_; ++i)
    v.every_vertex_lights[i] = every_vertex_lights_[i];
  v.every_vertex_count = every_vertex_count_;
  v.pick_lights = every_vertex_count_ < lights_.size();
  v.environment = environment_;
  v.environment_light = environment_light_;
  v.spawn_scale = spawn_scale_;
  return v;
}

std::size_t PreparedScene::triangle_bytes() const {
  std::size_t bytes = arrays_.of<PrimitiveType::kTriangle>().size() * sizeof(Triangle) +
                      triangle_attributes_.size() * sizeof(TriangleAttributes) +
                      triangle_accel_.stats().bytes +
                      instanced_triangles_.size() * sizeof(Triangle) +
                      instanced_attributes_.size() * sizeof(TriangleAttributes) +
                      mesh_placements_.size() * sizeof(MeshPlacement) + instance_accel_.bytes();
  for (const auto& mesh : shared_meshes_) bytes += mesh.stats().bytes;
  return bytes;
}

TileStats PreparedScene::render_tile(const TileRect& tile, std::span<float> rgba) const {
  std::fill(rgba.begin(), rgba.end(), 0.0f);
  FilmPlanes film;
  film.beauty = rgba.data();
  // AOV-enabled variants write only the planes that are present, so none are passed here.
  return variant_->render(view(), settings_, tile, film);
}

TileStats PreparedScene::render_tile(const TileRect& tile, TilePasses& passes) const {
  return refine_tile(tile, passes, 0, settings_.samples_per_pixel);
}

TileStats PreparedScene::refine_tile(const TileRect& tile, TilePasses& passes, std::uint32_t first,
                                     std::uint32_t end) const {
  if (first >= end)
    throw std::invalid_argument("refine_tile: first sample " + std::to_string(first) +
                                " is not below the end " + std::to_string(end));
  if (first > 0 && settings_.adaptive())
    throw std::invalid_argument("refine_tile: adaptive sampling renders in one pass");
  const FilmPlanes film = film_for(tile, passes, first);
  RenderSettings settings = settings_;
  settings.samples_per_pixel = end;
  // The beauty's alpha is the coverage the integrators add up; the AOV planes' fourth
  // component carries nothing.
  return variant_->render(view(), settings, tile, film);
}

FilmPlanes PreparedScene::film_for(const TileRect& tile, TilePasses& passes,
                                   std::uint32_t first) const {
  const std::size_t floats = tile.pixel_count() * 4;
  FilmPlanes film;
  film.first_sample = first;
  const auto prepare = [&](std::vector<float>& plane, float start) {
    if (first == 0) {
      plane.assign(floats, start);
    } else if (plane.size() != floats) {
      throw std::invalid_argument("refine_tile: the passes do not hold this tile");
    }
    return plane.data();
  };
  film.beauty = prepare(passes.beauty, 0.0f);
  for (std::size_t i = 0; i < passes.aovs.size(); ++i) {
    if ((settings_.aovs & (1u << i)) == 0) {
      passes.aovs[i].clear();
      continue;
    }
    aov_plane(film, i) = prepare(passes.aovs[i], aov_start(i));
  }
  return film;
}

TileStats PreparedScene::accumulate_tile(const TileRect& tile, TileAccumulation& state,
                                         std::uint32_t end) const {
  const std::uint32_t total = settings_.samples_per_pixel;
  const std::uint32_t first = state.samples_done;
  if (settings_.adaptive())
    throw std::invalid_argument("accumulate_tile: adaptive sampling renders in one pass");
  if (end <= first || end > total)
    throw std::invalid_argument("accumulate_tile: end " + std::to_string(end) + " is not in (" +
                                std::to_string(first) + ", " + std::to_string(total) + "]");
  if (first > 0 && state.samples_total != total)
    throw std::invalid_argument("accumulate_tile: the state is of a render of " +
                                std::to_string(state.samples_total) + " samples, not " +
                                std::to_string(total));
  const std::size_t floats = tile.pixel_count() * 4;
  const bool variance = (settings_.aovs & kAovVariance) != 0;
  FilmPlanes film;
  film.first_sample = first;
  film.total_samples = total;
  float** planes[] = {&film.albedo,       &film.normal,   &film.depth,
                      &film.primitive_id, &film.variance, &film.sample_count};
  static_assert(std::size(planes) == kAovCount);
  const auto prepare = [&](std::vector<float>& plane, float start) {
    if (first == 0) {
      plane.assign(floats, start);
    } else if (plane.size() != floats) {
      throw std::invalid_argument("accumulate_tile: the state does not hold this tile");
    }
    return plane.data();
  };
  film.beauty = prepare(state.sums.beauty, 0.0f);
  for (std::size_t i = 0; i < state.sums.aovs.size(); ++i) {
    if ((settings_.aovs & (1u << i)) == 0) {
      state.sums.aovs[i].clear();
      continue;
    }
    *planes[i] = prepare(state.sums.aovs[i], planes[i] == &film.depth ? kInfinity : 0.0f);
  }
  if (variance) {
    film.running_mean = prepare(state.running_mean, 0.0f);
    film.running_m2 = prepare(state.running_m2, 0.0f);
  } else {
    state.running_mean.clear();
    state.running_m2.clear();
  }
  state.samples_total = total;
  RenderSettings settings = settings_;
  settings.samples_per_pixel = end;
  const TileStats stats = variant_->render(view(), settings, tile, film);
  state.samples_done = end;
  return stats;
}

}  // namespace tessera
