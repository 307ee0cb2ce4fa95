#include "tessera/scene/scene_description.hpp"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/scene/scene_error.hpp"
#include "tessera/scene/spline_geometry.hpp"

namespace tessera {

std::string SceneIssue::to_string() const {
  std::ostringstream out;
  if (!file.empty()) {
    out << file;
    if (line > 0) out << ':' << line;
    out << ": ";
  }
  if (!field.empty()) out << field << ": ";
  out << message;
  return out.str();
}

namespace {
struct MaterialName {
  MaterialType type;
  const char* name;
};
constexpr MaterialName kMaterialNames[] = {
    {MaterialType::kLambertian, "lambertian"},
    {MaterialType::kLight, "light"},
    {MaterialType::kMetal, "metal"},
    {MaterialType::kRoughMirror, "rough_mirror"},
    {MaterialType::kGlass, "glass"},
    {MaterialType::kAnisotropicMetal, "anisotropic_metal"},
    {MaterialType::kClearCoat, "clear_coat"},
    {MaterialType::kThinFilm, "thin_film"},
};
}  // namespace

const char* to_string(MaterialType type) {
  for (const auto& entry : kMaterialNames)
    if (entry.type == type) return entry.name;
  return "unknown";
}

std::optional<MaterialType> material_type_from_string(const std::string& name) {
  for (const auto& entry : kMaterialNames)
    if (name == entry.name) return entry.type;
  return std::nullopt;
}

namespace {
struct IntegratorName {
  IntegratorKind kind;
  const char* name;
};
constexpr IntegratorName kIntegratorNames[] = {
    {IntegratorKind::kPath, "path"},     {IntegratorKind::kNormals, "normals"},
    {IntegratorKind::kShadow, "shadow"}, {IntegratorKind::kTransparency, "transparency"},
    {IntegratorKind::kAlbedo, "albedo"}, {IntegratorKind::kDepth, "depth"},
};
}  // namespace

const char* to_string(IntegratorKind kind) {
  for (const auto& entry : kIntegratorNames)
    if (entry.kind == kind) return entry.name;
  return "unknown";
}

std::optional<IntegratorKind> integrator_from_string(const std::string& name) {
  for (const auto& entry : kIntegratorNames)
    if (name == entry.name) return entry.kind;
  return std::nullopt;
}

std::optional<AovBit> aov_from_string(const std::string& name) {
  for (std::uint32_t i = 0; i < std::size(kAovNames); ++i)
    if (name == kAovNames[i]) return static_cast<AovBit>(1u << i);
  return std::nullopt;
}

glm::dmat4 TransformDesc::matrix() const {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
  if (rotate_degrees != 0.0 && glm::length(rotate_axis) > 0.0)
    m = glm::rotate(m, glm::radians(rotate_degrees), glm::normalize(rotate_axis));
  return glm::scale(m, scale);
}

TriangleMeshDesc transformed_mesh(const TriangleMeshDesc& mesh, const TransformDesc& transform) {
  TriangleMeshDesc out = mesh;
  const glm::dmat4 m = transform.matrix();
  const glm::dmat3 linear(m);
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  for (auto& p : out.positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  for (auto& n : out.normals) {
    const glm::dvec3 mapped = normal_matrix * n;
    const double length = glm::length(mapped);
    n = length > 0.0 ? mapped / length : mapped;
  }
  return out;
}

std::size_t SceneDescription::analytic_shape_count() const {
  return spheres.size() + quads.size() + planes.size() + disks.size() + cylinders.size() +
         cones.size() + tori.size() + sdf_boxes.size() + sdf_tori.size() + sdf_capsules.size() +
         patches.size() + trimmed_faces.size();
}

std::vector<double> clamped_uniform_knots(std::uint32_t count) {
  std::vector<double> knots;
  if (count < 4) return knots;
  knots.reserve(count + 4);
  for (int i = 0; i < 4; ++i) knots.push_back(0.0);
  const std::uint32_t spans = count - 3;
  for (std::uint32_t i = 1; i < spans; ++i) knots.push_back(static_cast<double>(i) / spans);
  for (int i = 0; i < 4; ++i) knots.push_back(1.0);
  return knots;
}

const char* trimmed_surface_name(const TrimmedSurfaceDesc& surface) {
  constexpr const char* kNames[] = {"plane",    "disk", "rectangle", "sphere",
                                    "cylinder", "cone", "torus",     "bspline_patch"};
  return kNames[surface.index()];
}

SplinePatchDescription to_spline_patch_description(const SplinePatchDesc& desc, bool placed) {
  SplinePatchDescription out;
  out.count_u = static_cast<int>(desc.count_u);
  out.count_v = static_cast<int>(desc.count_v);
  out.control_points = desc.control_points;
  if (placed && desc.transform) {
    const glm::dmat4 m = desc.transform->matrix();
    for (auto& p : out.control_points) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  }
  out.weights = desc.weights;
  out.knots_u = desc.knots_u.empty() ? clamped_uniform_knots(desc.count_u) : desc.knots_u;
  out.knots_v = desc.knots_v.empty() ? clamped_uniform_knots(desc.count_v) : desc.knots_v;
  out.material = desc.material;
  return out;
}

// The geometry module's own answer (uv_periodicity of the surface type), so validation
// unwraps loops exactly as the renderer's build does.
UvPeriodicity trimmed_surface_periodicity(const TrimmedSurfaceDesc& surface) {
  switch (surface.index()) {
    case 0:
      return uv_periodicity(Plane{});
    case 1:
      return uv_periodicity(Disk{});
    case 2:
      return uv_periodicity(Quad{});
    case 3:
      return uv_periodicity(Sphere{});
    case 4:
      return uv_periodicity(Cylinder{});
    case 5:
      return uv_periodicity(Cone{});
    case 6:
      return uv_periodicity(Torus{});
    default:
      return uv_periodicity(SplinePatch{});
  }
}

std::size_t SceneDescription::triangle_count() const {
  std::size_t count = 0;
  for (const auto& mesh : meshes) count += mesh.indices.size() / 3;
  return count;
}

std::optional<std::uint32_t> SceneDescription::find_material(const std::string& name) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return static_cast<std::uint32_t>(i);
  return std::nullopt;
}

namespace {

class Validator {
 public:
  explicit Validator(std::vector<SceneIssue>& issues) : issues_(issues) {}

  void fail(std::string field, std::string message) {
    issues_.push_back(SceneIssue{"", 0, std::move(field), std::move(message)});
  }
  bool finite(const std::string& field, double value) {
    if (std::isfinite(value)) return true;
    fail(field, "must be a finite number, got " + format(value));
    return false;
  }
  bool finite(const std::string& field, const glm::dvec3& v) {
    if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) return true;
    fail(field, "must be three finite numbers, got [" + format(v.x) + ", " + format(v.y) + ", " +
                    format(v.z) + "]");
    return false;
  }
  void in_range(const std::string& field, double value, double lo, double hi) {
    if (!finite(field, value)) return;
    if (value < lo || value > hi)
      fail(field, "must be in [" + format(lo) + ", " + format(hi) + "], got " + format(value));
  }
  // A length, radius or size: finite and > 0.
  bool positive(const std::string& field, double value) {
    if (!finite(field, value)) return false;
    if (value > 0.0) return true;
    fail(field, "must be > 0, got " + format(value));
    return false;
  }
  bool non_zero(const std::string& field, const glm::dvec3& v) {
    if (!finite(field, v)) return false;
    if (glm::length(v) > 0.0) return true;
    fail(field, "must not be the zero vector");
    return false;
  }
  void non_negative(const std::string& field, const glm::dvec3& v) {
    if (!finite(field, v)) return;
    if (v.x < 0 || v.y < 0 || v.z < 0) fail(field, "components must not be negative");
  }
  static std::string format(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
  }

 private:
  std::vector<SceneIssue>& issues_;
};

std::string geometry_field(std::uint32_t index, const char* name) {
  return "geometry[" + std::to_string(index) + "]." + name;
}

}  // namespace

std::vector<SceneIssue> validate_scene(const SceneDescription& scene, const SceneLimits& limits) {
  std::vector<SceneIssue> issues;
  Validator check(issues);

  const auto& cam = scene.camera;
  check.finite("camera.position", cam.position);
  check.finite("camera.look_at", cam.look_at);
  check.finite("camera.up", cam.up);
  check.in_range("camera.fov", cam.fov_degrees, 1e-3, 179.0);
  if (glm::length(cam.look_at - cam.position) == 0.0)
    check.fail("camera.look_at", "must differ from camera.position");
  else if (glm::length(glm::cross(cam.look_at - cam.position, cam.up)) == 0.0)
    check.fail("camera.up", "must not be parallel to the viewing direction");

  check.non_negative("settings.background_color", scene.background.color);
  check.in_range("settings.background_intensity", scene.background.intensity, 0.0, 1e6);

  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const auto& m = scene.materials[i];
    const std::string base = "materials[" + std::to_string(i) + "].";
    if (m.name.empty()) check.fail(base + "name", "must not be empty");
    for (std::size_t j = 0; j < i; ++j)
      if (scene.materials[j].name == m.name && !m.name.empty())
        check.fail(base + "name", "duplicate material name '" + m.name + "'");
    check.non_negative(base + "albedo", m.albedo);
    check.non_negative(base + "emission", m.emission);
    check.in_range(base + "roughness", m.roughness, 0.0, 1.0);
    check.in_range(base + "refractive_index", m.refractive_index, 1.0, 4.0);
    check.in_range(base + "metallic", m.metallic, 0.0, 1.0);
    check.in_range(base + "transmission", m.transmission, 0.0, 1.0);
    check.in_range(base + "anisotropy", m.anisotropy, -1.0, 1.0);
    check.in_range(base + "film_thickness", m.film_thickness, 0.0, 1e5);
    check.in_range(base + "film_ior", m.film_ior, 1.0, 4.0);
  }

  const auto material_ok = [&](std::uint32_t source, std::uint32_t material) {
    if (material >= scene.materials.size())
      check.fail(geometry_field(source, "material"),
                 "refers to material index " + std::to_string(material) + " but the scene has " +
                     std::to_string(scene.materials.size()));
  };
  const auto emits = [&](std::uint32_t material) {
    if (material >= scene.materials.size()) return false;
    const glm::dvec3& e = scene.materials[material].emission;
    return e.x > 0.0 || e.y > 0.0 || e.z > 0.0;
  };
  // The renderer samples emitting spheres, rectangles, triangles and disks for direct light
  // (spheres and disks only while their transform keeps them spheres and disks); any other
  // emitter is seen only by rays that hit it, which a hidden one never is.
  const auto hidden_emitter_ok = [&](std::uint32_t source, std::uint32_t material, bool visible,
                                     bool sampled) {
    if (!visible && !sampled && emits(material))
      check.fail(geometry_field(source, "visible"),
                 "an emitter of this shape type (or under a non-uniform scale) is only seen by "
                 "rays that hit it, so it must be visible");
  };
  const auto transform_ok = [&](std::uint32_t source, const std::optional<TransformDesc>& t) {
    if (!t) return;
    const std::string base = geometry_field(source, "transform");
    check.finite(base + ".translate", t->translate);
    check.non_zero(base + ".rotate.axis", t->rotate_axis);
    check.finite(base + ".rotate.degrees", t->rotate_degrees);
    if (check.finite(base + ".scale", t->scale) &&
        (t->scale.x == 0.0 || t->scale.y == 0.0 || t->scale.z == 0.0))
      check.fail(base + ".scale", "components must not be zero (the transform would be singular)");
  };
  const auto uniform = [](const std::optional<TransformDesc>& t) {
    return !t || t->uniform_scale();
  };

  for (const auto& s : scene.spheres) {
    check.finite(geometry_field(s.source_index, "center"), s.center);
    if (check.finite(geometry_field(s.source_index, "radius"), s.radius) && !(s.radius > 0.0))
      check.fail(geometry_field(s.source_index, "radius"),
                 "must be positive, got " + Validator::format(s.radius));
    material_ok(s.source_index, s.material);
    transform_ok(s.source_index, s.transform);
    hidden_emitter_ok(s.source_index, s.material, s.visible, uniform(s.transform));
  }
  for (const auto& q : scene.quads) {
    const bool ok = check.finite(geometry_field(q.source_index, "corner"), q.corner) &
                    check.finite(geometry_field(q.source_index, "u"), q.u) &
                    check.finite(geometry_field(q.source_index, "v"), q.v);
    if (ok && glm::length(glm::cross(q.u, q.v)) == 0.0)
      check.fail(geometry_field(q.source_index, "v"),
                 "u and v must span a parallelogram (they are parallel or zero)");
    material_ok(q.source_index, q.material);
    transform_ok(q.source_index, q.transform);
  }
  for (const auto& p : scene.planes) {
    check.finite(geometry_field(p.source_index, "point"), p.point);
    check.non_zero(geometry_field(p.source_index, "normal"), p.normal);
    material_ok(p.source_index, p.material);
    transform_ok(p.source_index, p.transform);
    if (emits(p.material))
      check.fail(geometry_field(p.source_index, "material"),
                 "an infinite plane cannot emit light (its power would be infinite); use the "
                 "background or a large rectangle or disk");
  }
  for (const auto& d : scene.disks) {
    const auto at = [&](const char* name) { return geometry_field(d.source_index, name); };
    check.finite(at("center"), d.center);
    check.non_zero(at("normal"), d.normal);
    if (check.positive(at("radius"), d.radius) &&
        check.finite(at("inner_radius"), d.inner_radius) &&
        !(d.inner_radius >= 0.0 && d.inner_radius < d.radius))
      check.fail(at("inner_radius"), "must be in [0, radius) = [0, " + Validator::format(d.radius) +
                                         "), got " + Validator::format(d.inner_radius));
    material_ok(d.source_index, d.material);
    transform_ok(d.source_index, d.transform);
    hidden_emitter_ok(d.source_index, d.material, d.visible, uniform(d.transform));
  }
  for (const auto& c : scene.cylinders) {
    const auto at = [&](const char* name) { return geometry_field(c.source_index, name); };
    check.finite(at("base"), c.base);
    check.non_zero(at("axis"), c.axis);
    check.positive(at("radius"), c.radius);
    check.positive(at("height"), c.height);
    material_ok(c.source_index, c.material);
    transform_ok(c.source_index, c.transform);
    hidden_emitter_ok(c.source_index, c.material, c.visible, false);
  }
  for (const auto& c : scene.cones) {
    const auto at = [&](const char* name) { return geometry_field(c.source_index, name); };
    check.finite(at("base"), c.base);
    check.non_zero(at("axis"), c.axis);
    check.positive(at("height"), c.height);
    const bool radii_finite = check.finite(at("base_radius"), c.base_radius) &
                              check.finite(at("top_radius"), c.top_radius);
    if (radii_finite) {
      if (c.base_radius < 0.0)
        check.fail(at("base_radius"), "must be >= 0, got " + Validator::format(c.base_radius));
      if (c.top_radius < 0.0)
        check.fail(at("top_radius"), "must be >= 0, got " + Validator::format(c.top_radius));
      if (c.base_radius == 0.0 && c.top_radius == 0.0)
        check.fail(at("base_radius"), "base_radius and top_radius must not both be 0");
    }
    material_ok(c.source_index, c.material);
    transform_ok(c.source_index, c.transform);
    hidden_emitter_ok(c.source_index, c.material, c.visible, false);
  }
  for (const auto& t : scene.tori) {
    const auto at = [&](const char* name) { return geometry_field(t.source_index, name); };
    check.finite(at("center"), t.center);
    check.non_zero(at("axis"), t.axis);
    check.positive(at("major_radius"), t.major_radius);
    check.positive(at("minor_radius"), t.minor_radius);
    material_ok(t.source_index, t.material);
    transform_ok(t.source_index, t.transform);
    hidden_emitter_ok(t.source_index, t.material, t.visible, false);
  }
  for (const auto& b : scene.sdf_boxes) {
    const auto at = [&](const char* name) { return geometry_field(b.source_index, name); };
    check.finite(at("center"), b.center);
    if (check.finite(at("half_extent"), b.half_extent)) {
      if (!(b.half_extent.x > 0.0 && b.half_extent.y > 0.0 && b.half_extent.z > 0.0))
        check.fail(at("half_extent"), "components must be > 0");
      else if (check.finite(at("rounding"), b.rounding)) {
        const double smallest =
            glm::min(b.half_extent.x, glm::min(b.half_extent.y, b.half_extent.z));
        if (!(b.rounding >= 0.0 && b.rounding <= smallest))
          check.fail(at("rounding"), "must be in [0, smallest half extent] = [0, " +
                                         Validator::format(smallest) + "], got " +
                                         Validator::format(b.rounding));
      }
    }
    material_ok(b.source_index, b.material);
    transform_ok(b.source_index, b.transform);
    hidden_emitter_ok(b.source_index, b.material, b.visible, false);
  }
  for (const auto& t : scene.sdf_tori) {
    const auto at = [&](const char* name) { return geometry_field(t.source_index, name); };
    check.finite(at("center"), t.center);
    check.non_zero(at("axis"), t.axis);
    if (check.positive(at("major_radius"), t.major_radius) &&
        check.positive(at("minor_radius"), t.minor_radius) && !(t.minor_radius < t.major_radius))
      check.fail(at("minor_radius"),
                 "must be < major_radius (" + Validator::format(t.major_radius) +
                     ") for a signed-distance torus, got " + Validator::format(t.minor_radius));
    material_ok(t.source_index, t.material);
    transform_ok(t.source_index, t.transform);
    hidden_emitter_ok(t.source_index, t.material, t.visible, false);
  }
  for (const auto& c : scene.sdf_capsules) {
    const auto at = [&](const char* name) { return geometry_field(c.source_index, name); };
    check.finite(at("a"), c.a);
    check.finite(at("b"), c.b);
    check.positive(at("radius"), c.radius);
    material_ok(c.source_index, c.material);
    transform_ok(c.source_index, c.transform);
    hidden_emitter_ok(c.source_index, c.material, c.visible, false);
  }
  // Patches and trimming loops are checked by building them (the builders name the field
  // and the reason); sizes are bounded first so no input allocates without limit.
  std::size_t control_points = 0, trim_points = 0;
  const auto add_issue = [&](const std::string& error) {
    const std::size_t colon = error.find(": ");
    if (colon == std::string::npos)
      check.fail("", error);
    else
      check.fail(error.substr(0, colon), error.substr(colon + 2));
  };
  const auto patch_ok = [&](const SplinePatchDesc& p, const std::string& base) {
    if (p.count_u < 4 || p.count_v < 4) {
      check.fail(base + (p.count_u < 4 ? ".count_u" : ".count_v"),
                 "must be at least 4 (bicubic), got " +
                     std::to_string(p.count_u < 4 ? p.count_u : p.count_v));
      return;
    }
    const std::size_t count = std::size_t{p.count_u} * p.count_v;
    if (p.control_points.size() != count) {
      check.fail(base + ".control_points",
                 "must have count_u * count_v = " + std::to_string(count) + " points, got " +
                     std::to_string(p.control_points.size()));
      return;
    }
    // Counted from the points actually given, so the limit bounds what building allocates.
    control_points += count;
    if (control_points > limits.max_patch_control_points) return;  // reported below
    SplinePatchPool pool;
    SplinePatch patch;
    const std::string error =
        build_spline_patch(to_spline_patch_description(p, false), pool, patch, base);
    if (!error.empty()) add_issue(error);
  };
  for (const auto& p : scene.patches) {
    const std::string base = "geometry[" + std::to_string(p.source_index) + "]";
    patch_ok(p, base);
    material_ok(p.source_index, p.material);
    transform_ok(p.source_index, p.transform);
    hidden_emitter_ok(p.source_index, p.material, p.visible, false);
  }
  for (const auto& f : scene.trimmed_faces) {
    const std::string base = "geometry[" + std::to_string(f.source_index) + "]";
    if (const auto* patch = std::get_if<SplinePatchDesc>(&f.surface)) {
      patch_ok(*patch, base + ".surface");
    } else {
      // The analytic surface is checked by the rules above, in a scene of its own, and its
      // issues are renamed from geometry[i].x to geometry[i].surface.x.
      SceneDescription alone;
      alone.materials.emplace_back().name = "surface";
      std::visit(
          [&](auto s) {
            using S = decltype(s);
            s.material = 0;
            s.visible = true;
            s.transform = std::nullopt;
            s.source_index = f.source_index;
            if constexpr (std::is_same_v<S, PlaneDesc>) alone.planes.push_back(s);
            if constexpr (std::is_same_v<S, DiskDesc>) alone.disks.push_back(s);
            if constexpr (std::is_same_v<S, QuadDesc>) alone.quads.push_back(s);
            if constexpr (std::is_same_v<S, SphereDesc>) alone.spheres.push_back(s);
            if constexpr (std::is_same_v<S, CylinderDesc>) alone.cylinders.push_back(s);
            if constexpr (std::is_same_v<S, ConeDesc>) alone.cones.push_back(s);
            if constexpr (std::is_same_v<S, TorusDesc>) alone.tori.push_back(s);
          },
          f.surface);
      for (SceneIssue issue : validate_scene(alone, limits)) {
        if (issue.field.rfind(base + ".", 0) == 0)
          issue.field = base + ".surface" + issue.field.substr(base.size());
        issues.push_back(std::move(issue));
      }
    }
    std::size_t points = 0;
    for (const auto& loop : f.loops) points += loop.size();
    trim_points += points;
    if (trim_points <= limits.max_trim_points) {
      TrimPool pool;
      TrimRegion region;
      const std::string error =
          build_trim_region(f.loops, trimmed_surface_periodicity(f.surface), pool, region, base);
      if (!error.empty()) add_issue(error);
    }
    material_ok(f.source_index, f.material);
    transform_ok(f.source_index, f.transform);
    hidden_emitter_ok(f.source_index, f.material, f.visible, false);
  }
  if (control_points > limits.max_patch_control_points)
    check.fail("geometry", "scene has " + std::to_string(control_points) +
                               " patch control points, more than the limit of " +
                               std::to_string(limits.max_patch_control_points));
  if (trim_points > limits.max_trim_points)
    check.fail("geometry", "scene has " + std::to_string(trim_points) +
                               " trimming loop points, more than the limit of " +
                               std::to_string(limits.max_trim_points));

  std::size_t triangles = 0;
  for (const auto& mesh : scene.meshes) {
    const std::string where = mesh.source_file.empty() ? "" : " (" + mesh.source_file + ")";
    if (mesh.indices.size() % 3 != 0)
      check.fail(geometry_field(mesh.source_index, "indices"),
                 "count must be a multiple of 3" + where);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      if (!check.finite(geometry_field(mesh.source_index, "positions") + "[" + std::to_string(i) +
                            "]" + where,
                        mesh.positions[i]))
        break;
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
      if (mesh.indices[i] >= mesh.positions.size()) {
        check.fail(geometry_field(mesh.source_index, "indices") + "[" + std::to_string(i) + "]",
                   "vertex index " + std::to_string(mesh.indices[i]) + " out of range (" +
                       std::to_string(mesh.positions.size()) + " vertices)" + where);
        break;
      }
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      check.fail(geometry_field(mesh.source_index, "normals"),
                 "must be empty or one per vertex (" + std::to_string(mesh.positions.size()) +
                     "), got " + std::to_string(mesh.normals.size()) + where);
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
      check.fail(geometry_field(mesh.source_index, "uvs"),
                 "must be empty or one per vertex (" + std::to_string(mesh.positions.size()) +
                     "), got " + std::to_string(mesh.uvs.size()) + where);
    material_ok(mesh.source_index, mesh.material);
    transform_ok(mesh.source_index, mesh.transform);
    triangles += mesh.indices.size() / 3;
  }
  if (triangles > limits.max_triangles)
    check.fail("geometry", "scene has " + std::to_string(triangles) +
                               " triangles, more than the limit of " +
                               std::to_string(limits.max_triangles));
  // The renderer names triangles (baked, or each placement's of shared geometry) with the
  // 27 index bits of a primitive reference, whatever limit a server configures.
  constexpr std::size_t kNamedTriangles = std::size_t{1} << 27;
  if (triangles > kNamedTriangles)
    check.fail("geometry", "scene has " + std::to_string(triangles) +
                               " triangles, more than the renderer can name (2^27)");
  const std::size_t per_type[] = {
      scene.spheres.size(),      scene.quads.size(),     scene.planes.size(),
      scene.disks.size(),        scene.cylinders.size(), scene.cones.size(),
      scene.tori.size(),         scene.sdf_boxes.size(), scene.sdf_tori.size(),
      scene.sdf_capsules.size(), scene.patches.size(),   scene.trimmed_faces.size()};
  for (std::size_t count : per_type)
    if (count > limits.max_shapes_per_type) {
      check.fail("geometry", "scene has " + std::to_string(count) +
                                 " shapes of one type, more than the limit of " +
                                 std::to_string(limits.max_shapes_per_type));
      break;
    }

  const auto& r = scene.render;
  const auto in_u32 = [&](const char* name, std::uint32_t value, std::uint32_t lo,
                          std::uint32_t hi) {
    if (value < lo || value > hi)
      check.fail(std::string("render.") + name, "must be in [" + std::to_string(lo) + ", " +
                                                    std::to_string(hi) + "], got " +
                                                    std::to_string(value));
  };
  in_u32("width", r.width, 1, limits.max_dimension);
  in_u32("height", r.height, 1, limits.max_dimension);
  in_u32("spp", r.samples_per_pixel, 1, limits.max_samples_per_pixel);
  in_u32("max_depth", r.max_depth, 1, limits.max_depth);
  in_u32("tile_size", r.tile_size, limits.min_tile_size, limits.max_tile_size);
  if ((r.aovs & ~kAllAovs) != 0) check.fail("render.aovs", "unknown AOV bits set");
  if (r.aovs != 0 && r.integrator != IntegratorKind::kPath)
    check.fail("render.aovs", std::string("AOVs come with the path integrator, not '") +
                                  to_string(r.integrator) + "'");
  return issues;
}

}  // namespace tessera
