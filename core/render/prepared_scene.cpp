#include "tessera/render/prepared_scene.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "tessera/scene/spline_geometry.hpp"

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

// A geometry entry's transform, in the forms baking and instancing need.
struct Placement {
  AffineTransform affine;  // identity when the entry has none
  double scale = 1.0;      // |uniform scale|, for lengths of baked shapes

  explicit Placement(const std::optional<TransformDesc>& transform) {
    if (!transform) return;
    const glm::dmat4 m = transform->matrix();
    affine.linear = glm::dmat3(m);
    affine.translation = glm::dvec3(m[3]);
    scale = std::fabs(transform->scale.x);
  }
  vec3 point(const glm::dvec3& p) const { return vec3(affine.point(p)); }
  vec3 vector(const glm::dvec3& v) const { return vec3(affine.vector(v)); }
  // A direction: unit, mapped by the linear part (axes of shapes under a similarity).
  vec3 direction(const glm::dvec3& v) const { return vec3(glm::normalize(affine.vector(v))); }
  // A surface normal: by the inverse transpose, so it stays perpendicular under any map.
  vec3 normal(const glm::dvec3& n) const {
    return vec3(glm::normalize(glm::transpose(glm::inverse(affine.linear)) * n));
  }
  float length(double l) const { return static_cast<float>(l * scale); }
};

// The instance of `shape` placed by `transform` (validated non-singular before this runs).
template <typename Shape>
Instance<Shape> make_instance(const Shape& shape, const std::optional<TransformDesc>& transform) {
  Instance<Shape> instance;
  if (!Instance<Shape>::make(shape, Placement(transform).affine, instance))
    throw std::invalid_argument("singular geometry transform (validate_scene rejects these)");
  return instance;
}

// Each surface type built from its description where `at` puts it: the identity placement
// gives the surface in its own space (for instances and trimmed faces); a similarity gives
// the baked world shape (lengths scale by |s|, axes rotate, normals by the inverse
// transpose). `material` is the entry's own, or the face's for a trimmed surface.
const Placement kObjectSpace{std::nullopt};

Plane placed_surface(const PlaneDesc& p, const Placement& at, std::uint32_t material) {
  return Plane::make(at.point(p.point), at.normal(p.normal), material);
}
Disk placed_surface(const DiskDesc& d, const Placement& at, std::uint32_t material) {
  return Disk::make(at.point(d.center), at.direction(d.normal), at.length(d.radius), material,
                    at.length(d.inner_radius));
}
Quad placed_surface(const QuadDesc& q, const Placement& at, std::uint32_t material) {
  // A parallelogram stays one under any affine map.
  return Quad::make(at.point(q.corner), at.vector(q.u), at.vector(q.v), material);
}
Sphere placed_surface(const SphereDesc& s, const Placement& at, std::uint32_t material) {
  return Sphere{at.point(s.center), at.length(s.radius), material};
}
Cylinder placed_surface(const CylinderDesc& c, const Placement& at, std::uint32_t material) {
  return Cylinder::make(at.point(c.base), at.direction(c.axis), at.length(c.radius),
                        at.length(c.height), c.caps, material);
}
Cone placed_surface(const ConeDesc& c, const Placement& at, std::uint32_t material) {
  return Cone::make(at.point(c.base), at.direction(c.axis), at.length(c.base_radius),
                    at.length(c.top_radius), at.length(c.height), c.caps, material);
}
Torus placed_surface(const TorusDesc& t, const Placement& at, std::uint32_t material) {
  return Torus::make(at.point(t.center), at.direction(t.axis), at.length(t.major_radius),
                     at.length(t.minor_radius), material);
}
// Build errors were reported by validate_scene already; one here means a caller skipped it.
void require_built(const std::string& error) {
  if (!error.empty())
    throw std::invalid_argument(error + " (validate_scene rejects such scenes before rendering)");
}

// Per-vertex shading data of one mesh triangle; meshes without normals get zero normals
// (they shade flat), without uvs the uvs that reproduce barycentric uvs.
TriangleAttributes mesh_attributes(const TriangleMeshDesc& mesh, std::uint32_t a, std::uint32_t b,
                                   std::uint32_t c) {
  TriangleAttributes shading{vec3(0.0f), vec3(0.0f),       vec3(0.0f),
                             vec2(0.0f), vec2(1.0f, 0.0f), vec2(0.0f, 1.0f)};
  if (mesh.normals.size() == mesh.positions.size()) {
    shading.n0 = to_float(mesh.normals[a]);
    shading.n1 = to_float(mesh.normals[b]);
    shading.n2 = to_float(mesh.normals[c]);
  }
  if (mesh.uvs.size() == mesh.positions.size()) {
    shading.uv0 = vec2(mesh.uvs[a]);
    shading.uv1 = vec2(mesh.uvs[b]);
    shading.uv2 = vec2(mesh.uvs[c]);
  }
  return shading;
}

bool same_geometry(const TriangleMeshDesc& a, const TriangleMeshDesc& b) {
  return a.indices == b.indices && a.positions == b.positions && a.normals == b.normals &&
         a.uvs == b.uvs;
}

// FNV-1a over the geometry's 8-byte words (every array holds whole words but the
// indices, whose odd tail is mixed alone): equal meshes hash alike, same_geometry confirms.
// Word-wise, it costs about as much as reading the mesh once.
std::uint64_t geometry_hash(const TriangleMeshDesc& mesh) {
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t word;
      std::memcpy(&word, p + i, 8);
      h = (h ^ word) * 1099511628211ull;
    }
    for (; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  mix(mesh.positions.data(), mesh.positions.size() * sizeof(glm::dvec3));
  mix(mesh.normals.data(), mesh.normals.size() * sizeof(glm::dvec3));
  mix(mesh.uvs.data(), mesh.uvs.size() * sizeof(glm::dvec2));
  return h;
}

// Mesh entries (indices into description.meshes) that share one geometry, for every
// geometry placed two or more times by visible, non-emitting entries. Found by content, so
// scenes that arrive over the API share as well as those whose loader shared the file.
// Emitters stay baked: lights are sampled per world triangle.
std::vector<std::vector<std::size_t>> shared_geometry_groups(
    const SceneDescription& description, const std::vector<Material>& materials) {
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_hash;  // into `groups`
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t m = 0; m < description.meshes.size(); ++m) {
    const TriangleMeshDesc& mesh = description.meshes[m];
    if (!mesh.visible || mesh.indices.size() < 3 || materials[mesh.material].emissive()) continue;
    auto& candidates = by_hash[geometry_hash(mesh)];
    const auto same = std::find_if(candidates.begin(), candidates.end(), [&](std::size_t g) {
      return same_geometry(description.meshes[groups[g].front()], mesh);
    });
    if (same != candidates.end()) {
      groups[*same].push_back(m);
    } else {
      candidates.push_back(groups.size());
      groups.push_back({m});
    }
  }
  std::erase_if(groups, [](const auto& group) { return group.size() < 2; });
  return groups;
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

  // Shapes go into their flat arrays; `place` stores one in `array` and records it under
  // `type` for the BVH (and the light list when the type has a sampler).
  const auto place = [&](auto& array, PrimitiveType type, const auto& shape, bool visible,
                         std::uint32_t material) {
    const auto index = static_cast<std::uint32_t>(array.size());
    array.push_back(shape);
    add(type, index, tessera::bounds(shape), visible, material,
        has_light_sampler(type) ? surface_area(shape) : 0.0f);
  };

  // Curved shapes are baked when the transform is a similarity (they stay the same shape
  // type) and instanced otherwise (non-uniform scale).
  const auto place_curved = [&](const auto& desc, auto& baked, PrimitiveType baked_type,
                                auto& instances, PrimitiveType instance_type) {
    if (transform_bakes_into_shape(desc.transform))
      place(baked, baked_type, placed_surface(desc, Placement(desc.transform), desc.material),
            desc.visible, desc.material);
    else
      place(instances, instance_type,
            make_instance(placed_surface(desc, kObjectSpace, desc.material), desc.transform),
            desc.visible, desc.material);
  };
  for (const auto& s : description.spheres)
    place_curved(s, scene->spheres_, PrimitiveType::kSphere, scene->sphere_instances_,
                 PrimitiveType::kSphereInstance);
  for (const auto& q : description.quads)
    place(scene->quads_, PrimitiveType::kQuad,
          placed_surface(q, Placement(q.transform), q.material), q.visible, q.material);
  // Shading attributes are stored only when some mesh has normals or uvs; the others then
  // get zero normals (shade flat) and the uvs that reproduce barycentric uvs.
  const bool attributes =
      std::any_of(description.meshes.begin(), description.meshes.end(),
                  [](const TriangleMeshDesc& m) { return !m.normals.empty() || !m.uvs.empty(); });
  std::vector<bool> shared(description.meshes.size(), false);
  const std::vector<std::vector<std::size_t>> groups =
      options.instancing ? shared_geometry_groups(description, scene->materials_)
                         : std::vector<std::vector<std::size_t>>{};
  for (const auto& group : groups)
    for (const std::size_t m : group) shared[m] = true;
  for (std::size_t m = 0; m < description.meshes.size(); ++m) {
    if (shared[m]) continue;
    const TriangleMeshDesc& source = description.meshes[m];
    const TriangleMeshDesc mesh =
        source.transform ? transformed_mesh(source, *source.transform) : TriangleMeshDesc{};
    const TriangleMeshDesc& placed = source.transform ? mesh : source;
    for (std::size_t i = 0; i + 2 < placed.indices.size(); i += 3) {
      const std::uint32_t a = placed.indices[i], b = placed.indices[i + 1],
                          c = placed.indices[i + 2];
      const Triangle tri{to_float(placed.positions[a]), to_float(placed.positions[b]),
                         to_float(placed.positions[c]), placed.material};
      place(scene->triangles_, PrimitiveType::kTriangle, tri, placed.visible, placed.material);
      if (attributes) scene->triangle_attributes_.push_back(mesh_attributes(placed, a, b, c));
    }
  }
  // Shared geometry: built once in object space, each placement an instance with its own
  // range of virtual triangle ids.
  scene->shared_meshes_.reserve(groups.size());  // the instances point into it
  std::vector<MeshInstance> instances;
  std::uint64_t next_id = 0;
  for (const auto& group : groups) {
    const TriangleMeshDesc& geometry = description.meshes[group.front()];
    const auto first_triangle = static_cast<std::uint32_t>(scene->instanced_triangles_.size());
    for (std::size_t i = 0; i + 2 < geometry.indices.size(); i += 3) {
      const std::uint32_t a = geometry.indices[i], b = geometry.indices[i + 1],
                          c = geometry.indices[i + 2];
      scene->instanced_triangles_.push_back(Triangle{to_float(geometry.positions[a]),
                                                     to_float(geometry.positions[b]),
                                                     to_float(geometry.positions[c]), 0});
      if (attributes) scene->instanced_attributes_.push_back(mesh_attributes(geometry, a, b, c));
    }
    const std::span<const Triangle> object(scene->instanced_triangles_.data() + first_triangle,
                                           scene->instanced_triangles_.size() - first_triangle);
    scene->shared_meshes_.push_back(TriangleAccel::build(object));
    for (const std::size_t m : group) {
      const TriangleMeshDesc& entry = description.meshes[m];
      if (next_id + object.size() > std::uint64_t{kPrimitiveIndexMask} + 1)
        throw std::invalid_argument(
            "geometry[" + std::to_string(entry.source_index) +
            "]: placements of shared meshes exceed 2^27 triangles in all (the reference's "
            "index bits)");
      MeshPlacement placement;
      placement.first_id = static_cast<std::uint32_t>(next_id);
      placement.first_triangle = first_triangle;
      placement.material = entry.material;
      placement.object_to_world = Placement(entry.transform).affine;
      placement.world_to_object = placement.object_to_world.inverse();
      scene->mesh_placements_.push_back(placement);
      instances.push_back(
          MeshInstance{&scene->shared_meshes_.back(),
                       entry.transform ? glm::mat4(entry.transform->matrix()) : glm::mat4(1.0f),
                       make_primitive_ref(PrimitiveType::kInstancedTriangle, placement.first_id)});
      next_id += object.size();
    }
  }
  if (!instances.empty()) {
    scene->instance_accel_ = InstanceAccel(std::move(instances));
    spdlog::info("{} mesh placements share {} geometries (two-level)",
                 scene->mesh_placements_.size(), scene->shared_meshes_.size());
  }
  for (const auto& p : description.planes) {
    if (!p.visible) continue;  // planes never emit, so a hidden one does nothing
    scene->planes_.push_back(placed_surface(p, Placement(p.transform), p.material));
  }
  for (const auto& d : description.disks)
    place_curved(d, scene->disks_, PrimitiveType::kDisk, scene->disk_instances_,
                 PrimitiveType::kDiskInstance);
  for (const auto& c : description.cylinders)
    place_curved(c, scene->cylinders_, PrimitiveType::kCylinder, scene->cylinder_instances_,
                 PrimitiveType::kCylinderInstance);
  for (const auto& c : description.cones)
    place_curved(c, scene->cones_, PrimitiveType::kCone, scene->cone_instances_,
                 PrimitiveType::kConeInstance);
  for (const auto& t : description.tori)
    place_curved(t, scene->tori_, PrimitiveType::kTorus, scene->torus_instances_,
                 PrimitiveType::kTorusInstance);
  // Signed-distance shapes: the box is axis-aligned in its own space, so a rotation needs an
  // instance anyway; every transformed one is instanced to keep one rule.
  const auto place_sdf = [&](const auto& desc, const auto& shape, auto& plain,
                             PrimitiveType plain_type, auto& instances,
                             PrimitiveType instance_type) {
    if (!desc.transform)
      place(plain, plain_type, shape, desc.visible, desc.material);
    else
      place(instances, instance_type, make_instance(shape, desc.transform), desc.visible,
            desc.material);
  };
  for (const auto& b : description.sdf_boxes)
    place_sdf(b,
              SdfBox{to_float(b.center), to_float(b.half_extent), static_cast<float>(b.rounding),
                     b.material},
              scene->sdf_boxes_, PrimitiveType::kSdfBox, scene->sdf_box_instances_,
              PrimitiveType::kSdfBoxInstance);
  for (const auto& t : description.sdf_tori)
    place_sdf(t,
              SdfTorus{to_float(t.center), vec3(glm::normalize(t.axis)),
                       static_cast<float>(t.major_radius), static_cast<float>(t.minor_radius),
                       t.material},
              scene->sdf_tori_, PrimitiveType::kSdfTorus, scene->sdf_torus_instances_,
              PrimitiveType::kSdfTorusInstance);
  for (const auto& c : description.sdf_capsules)
    place_sdf(c, SdfCapsule{to_float(c.a), to_float(c.b), static_cast<float>(c.radius), c.material},
              scene->sdf_capsules_, PrimitiveType::kSdfCapsule, scene->sdf_capsule_instances_,
              PrimitiveType::kSdfCapsuleInstance);

  // Patches: the transform is baked into the control points (exact: B-splines are affine
  // invariant), so the patch is stored as it stands in the world.
  for (const auto& p : description.patches) {
    SplinePatch patch;
    require_built(build_spline_patch(to_spline_patch_description(p, true), scene->patch_pool_,
                                     patch, "geometry[" + std::to_string(p.source_index) + "]"));
    const auto index = static_cast<std::uint32_t>(scene->patches_.size());
    scene->patches_.push_back(patch);
    add(PrimitiveType::kSplinePatch, index, tessera::bounds(patch), p.visible, p.material, 0.0f);
  }
  // Trimmed faces: each an instance of the trimmed surface in its own space.
  for (const auto& f : description.trimmed_faces) {
    const std::string field = "geometry[" + std::to_string(f.source_index) + "]";
    const auto store = [&](auto& array, PrimitiveType type, const auto& surface) {
      using Surface = std::decay_t<decltype(surface)>;
      Trimmed<Surface> face;
      require_built(build_trimmed_face(surface, f.loops, scene->trim_pool_, face, field));
      const auto index = static_cast<std::uint32_t>(array.size());
      array.push_back(make_instance(face, f.transform));
      add(type, index, tessera::bounds(array.back()), f.visible, f.material, 0.0f);
    };
    std::visit(
        [&](const auto& desc) {
          using D = std::decay_t<decltype(desc)>;
          if constexpr (std::is_same_v<D, SplinePatchDesc>) {
            SplinePatchDesc object = desc;
            object.material = f.material;
            SplinePatch patch;
            require_built(build_spline_patch(to_spline_patch_description(object, false),
                                             scene->patch_pool_, patch, field + ".surface"));
            store(scene->trimmed_patches_, PrimitiveType::kTrimmedPatch, patch);
          } else {
            const auto surface = placed_surface(desc, kObjectSpace, f.material);
            using S = std::decay_t<decltype(surface)>;
            if constexpr (std::is_same_v<S, Plane>)
              store(scene->trimmed_planes_, PrimitiveType::kTrimmedPlane, surface);
            else if constexpr (std::is_same_v<S, Disk>)
              store(scene->trimmed_disks_, PrimitiveType::kTrimmedDisk, surface);
            else if constexpr (std::is_same_v<S, Quad>)
              store(scene->trimmed_quads_, PrimitiveType::kTrimmedQuad, surface);
            else if constexpr (std::is_same_v<S, Sphere>)
              store(scene->trimmed_spheres_, PrimitiveType::kTrimmedSphere, surface);
            else if constexpr (std::is_same_v<S, Cylinder>)
              store(scene->trimmed_cylinders_, PrimitiveType::kTrimmedCylinder, surface);
            else if constexpr (std::is_same_v<S, Cone>)
              store(scene->trimmed_cones_, PrimitiveType::kTrimmedCone, surface);
            else
              store(scene->trimmed_tori_, PrimitiveType::kTrimmedTorus, surface);
          }
        },
        f.surface);
  }
  // Every pool has its final size now: point the shapes at where their data ended up.
  for (auto& patch : scene->patches_) bind_pieces(patch, scene->patch_pool_.pieces.data());
  const auto bind_faces = [&](auto& faces) {
    for (auto& face : faces) bind_trim_region(face.shape.region, scene->trim_pool_);
  };
  bind_faces(scene->trimmed_planes_);
  bind_faces(scene->trimmed_disks_);
  bind_faces(scene->trimmed_quads_);
  bind_faces(scene->trimmed_spheres_);
  bind_faces(scene->trimmed_cylinders_);
  bind_faces(scene->trimmed_cones_);
  bind_faces(scene->trimmed_tori_);
  bind_faces(scene->trimmed_patches_);
  for (auto& face : scene->trimmed_patches_)
    bind_pieces(face.shape.surface, scene->patch_pool_.pieces.data());

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
  v.triangle_attributes = triangle_attributes_.empty() ? nullptr : triangle_attributes_.data();
  v.planes = planes_.data();
  v.plane_count = static_cast<std::uint32_t>(planes_.size());
  v.disks = disks_.data();
  v.cylinders = cylinders_.data();
  v.cones = cones_.data();
  v.tori = tori_.data();
  v.sdf_boxes = sdf_boxes_.data();
  v.sdf_tori = sdf_tori_.data();
  v.sdf_capsules = sdf_capsules_.data();
  v.sphere_instances = sphere_instances_.data();
  v.disk_instances = disk_instances_.data();
  v.cylinder_instances = cylinder_instances_.data();
  v.cone_instances = cone_instances_.data();
  v.torus_instances = torus_instances_.data();
  v.sdf_box_instances = sdf_box_instances_.data();
  v.sdf_torus_instances = sdf_torus_instances_.data();
  v.sdf_capsule_instances = sdf_capsule_instances_.data();
  v.patches = patches_.data();
  v.trimmed_planes = trimmed_planes_.data();
  v.trimmed_disks = trimmed_disks_.data();
  v.trimmed_quads = trimmed_quads_.data();
  v.trimmed_spheres = trimmed_spheres_.data();
  v.trimmed_cylinders = trimmed_cylinders_.data();
  v.trimmed_cones = trimmed_cones_.data();
  v.trimmed_tori = trimmed_tori_.data();
  v.trimmed_patches = trimmed_patches_.data();
  v.materials = materials_.data();
  v.lights = lights_.data();
  v.light_count = static_cast<std::uint32_t>(lights_.size());
  v.bvh = bvh_.view();
  if (triangle_accel_.stats().triangles > 0) v.bvh.triangles = &triangle_accel_;
  v.instanced_triangles = instanced_triangles_.data();
  v.instanced_attributes = instanced_attributes_.empty() ? nullptr : instanced_attributes_.data();
  v.mesh_placements = mesh_placements_.data();
  v.mesh_placement_count = static_cast<std::uint32_t>(mesh_placements_.size());
  if (!mesh_placements_.empty()) v.bvh.instances = &instance_accel_;
  v.camera = camera_;
  v.background = background_;
  return v;
}

std::size_t PreparedScene::triangle_bytes() const {
  std::size_t bytes = triangles_.size() * sizeof(Triangle) +
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
