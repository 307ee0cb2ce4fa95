#include "server/scene_from_proto.hpp"

#include <cmath>
#include <sstream>

namespace tessera::server {
namespace {

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string indexed(const std::string& name, std::size_t index) {
  return name + "[" + std::to_string(index) + "]";
}

// Collects structural problems with the field paths of the protobuf messages.
class ProtoChecker {
 public:
  explicit ProtoChecker(std::vector<SceneIssue>& issues) : issues_(issues) {}

  void fail(std::string field, std::string message) {
    issues_.push_back(SceneIssue{"", 0, std::move(field), std::move(message)});
  }
  double number(const std::string& field, double value) {
    if (!std::isfinite(value)) fail(field, "must be a finite number, got " + format_number(value));
    return value;
  }
  glm::dvec3 vec3(const std::string& field, const v1::Vec3& v) {
    return glm::dvec3(number(field + ".x", v.x()), number(field + ".y", v.y()),
                      number(field + ".z", v.z()));
  }

 private:
  std::vector<SceneIssue>& issues_;
};

std::optional<MaterialType> material_type_from_proto(v1::MaterialType type) {
  switch (type) {
    case v1::MATERIAL_TYPE_LAMBERTIAN:
      return MaterialType::kLambertian;
    case v1::MATERIAL_TYPE_LIGHT:
      return MaterialType::kLight;
    case v1::MATERIAL_TYPE_METAL:
      return MaterialType::kMetal;
    case v1::MATERIAL_TYPE_ROUGH_MIRROR:
      return MaterialType::kRoughMirror;
    case v1::MATERIAL_TYPE_GLASS:
      return MaterialType::kGlass;
    case v1::MATERIAL_TYPE_ANISOTROPIC_METAL:
      return MaterialType::kAnisotropicMetal;
    case v1::MATERIAL_TYPE_CLEAR_COAT:
      return MaterialType::kClearCoat;
    case v1::MATERIAL_TYPE_THIN_FILM:
      return MaterialType::kThinFilm;
    default:
      return std::nullopt;
  }
}

// Metal colours the renderer knows (see make_material); anything else would silently
// fall back to the albedo.
bool known_metal_preset(const std::string& preset) {
  return preset.empty() || preset == "silver" || preset == "gold" || preset == "copper" ||
         preset == "aluminium" || preset == "aluminum";
}

void convert_camera(const v1::Scene& in, ProtoChecker& check, CameraDesc& cam) {
  if (!in.has_camera()) return;  // the same defaults as a YAML scene without a camera
  const v1::Camera& c = in.camera();
  if (c.has_position()) cam.position = check.vec3("camera.position", c.position());
  if (c.has_look_at()) cam.look_at = check.vec3("camera.look_at", c.look_at());
  if (c.has_up()) cam.up = check.vec3("camera.up", c.up());
  const double fov = check.number("camera.fov_degrees", c.fov_degrees());
  if (fov != 0.0) cam.fov_degrees = fov;
}

void convert_background(const v1::Scene& in, ProtoChecker& check, BackgroundDesc& bg) {
  if (!in.has_background()) return;
  const v1::Background& b = in.background();
  bg.color = check.vec3("background.color", b.color());
  if (b.has_intensity()) bg.intensity = check.number("background.intensity", b.intensity());
}

void convert_materials(const v1::Scene& in, ProtoChecker& check,
                       std::vector<MaterialDesc>& materials) {
  for (int i = 0; i < in.materials_size(); ++i) {
    const v1::Material& m = in.materials(i);
    const std::string base = indexed("materials", static_cast<std::size_t>(i)) + ".";
    MaterialDesc mat;
    mat.name = m.name();
    if (m.type() == v1::MATERIAL_TYPE_UNSPECIFIED) {
      check.fail(base + "type", "must be set (got MATERIAL_TYPE_UNSPECIFIED)");
    } else if (const auto type = material_type_from_proto(m.type())) {
      mat.type = *type;
    } else {
      check.fail(base + "type", "unknown material type " + std::to_string(m.type()));
    }
    if (mat.type == MaterialType::kLight) mat.albedo = glm::dvec3(1.0);
    if (m.has_albedo()) mat.albedo = check.vec3(base + "albedo", m.albedo());
    mat.emission = check.vec3(base + "emission", m.emission());
    if (mat.type == MaterialType::kLight && !m.has_emission())
      check.fail(base + "emission", "is required for a light material");
    mat.roughness = check.number(base + "roughness", m.roughness());
    if (m.has_refractive_index())
      mat.refractive_index = check.number(base + "refractive_index", m.refractive_index());
    mat.metallic = check.number(base + "metallic", m.metallic());
    mat.transmission = check.number(base + "transmission", m.transmission());
    mat.anisotropy = check.number(base + "anisotropy", m.anisotropy());
    mat.preset = m.preset();
    if (!known_metal_preset(mat.preset))
      check.fail(base + "preset", "unknown preset '" + mat.preset +
                                      "' (expected silver, gold, copper or aluminium)");
    mat.film_thickness = check.number(base + "film_thickness", m.film_thickness());
    if (m.has_film_ior()) mat.film_ior = check.number(base + "film_ior", m.film_ior());
    materials.push_back(std::move(mat));
  }
}

void convert_mesh(const v1::TriangleMesh& in, const std::string& path, ProtoChecker& check,
                  TriangleMeshDesc& mesh) {
  const auto& positions = in.positions();
  const auto& indices = in.indices();
  bool ok = true;
  if (positions.size() % 3 != 0) {
    check.fail(path + ".positions", "count must be a multiple of 3 (x, y, z per vertex), got " +
                                        std::to_string(positions.size()));
    ok = false;
  }
  for (int i = 0; i < positions.size(); ++i) {
    if (!std::isfinite(positions[i])) {
      check.fail(indexed(path + ".positions", static_cast<std::size_t>(i)),
                 "must be a finite number, got " + format_number(positions[i]));
      ok = false;
      break;  // one is enough; a broken mesh may have millions
    }
  }
  if (indices.empty()) {
    check.fail(path + ".indices", "must hold at least one triangle");
    ok = false;
  } else if (indices.size() % 3 != 0) {
    check.fail(path + ".indices", "count must be a multiple of 3 (three per triangle), got " +
                                      std::to_string(indices.size()));
    ok = false;
  }
  const auto vertex_count = static_cast<std::uint64_t>(positions.size() / 3);
  // With a partial vertex the count is unknown, so index ranges mean nothing yet.
  for (int i = 0; ok && i < indices.size(); ++i) {
    if (indices[i] >= vertex_count) {
      check.fail(indexed(path + ".indices", static_cast<std::size_t>(i)),
                 "vertex index " + std::to_string(indices[i]) + " out of range (" +
                     std::to_string(vertex_count) + " vertices)");
      ok = false;
      break;
    }
  }
  // Per-vertex attributes: none, or one per vertex, finite.
  const auto attribute_ok = [&](const google::protobuf::RepeatedField<double>& values,
                                const char* name, int per_vertex, const char* layout) {
    if (values.empty()) return true;
    if (static_cast<std::uint64_t>(values.size()) != vertex_count * per_vertex) {
      check.fail(path + "." + name, std::string("must be empty or ") + layout + " per vertex (" +
                                        std::to_string(vertex_count * per_vertex) +
                                        " numbers), got " + std::to_string(values.size()));
      return false;
    }
    for (int i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i])) {
        check.fail(indexed(path + "." + name, static_cast<std::size_t>(i)),
                   "must be a finite number, got " + format_number(values[i]));
        return false;
      }
    return true;
  };
  ok = attribute_ok(in.normals(), "normals", 3, "x, y, z") && ok;
  ok = attribute_ok(in.uvs(), "uvs", 2, "u, v") && ok;
  if (!ok) return;
  mesh.positions.reserve(vertex_count);
  for (int i = 0; i + 2 < positions.size(); i += 3)
    mesh.positions.emplace_back(positions[i], positions[i + 1], positions[i + 2]);
  mesh.indices.assign(indices.begin(), indices.end());
  for (int i = 0; i + 2 < in.normals().size(); i += 3)
    mesh.normals.emplace_back(in.normals(i), in.normals(i + 1), in.normals(i + 2));
  for (int i = 0; i + 1 < in.uvs().size(); i += 2) mesh.uvs.emplace_back(in.uvs(i), in.uvs(i + 1));
}

std::optional<TransformDesc> convert_transform(const v1::Geometry& g, const std::string& path,
                                               ProtoChecker& check) {
  if (!g.has_transform()) return std::nullopt;
  const v1::Transform& in = g.transform();
  const std::string base = path + ".transform";
  TransformDesc t;
  t.translate = check.vec3(base + ".translate", in.translate());
  if (in.has_rotate()) {
    t.rotate_axis = check.vec3(base + ".rotate.axis", in.rotate().axis());
    t.rotate_degrees = check.number(base + ".rotate.degrees", in.rotate().degrees());
  }
  if (in.has_scale()) t.scale = check.vec3(base + ".scale", in.scale());
  return t;
}

// The shape fields of each message (the Geometry's fields are filled by the caller); `at`
// is the message's path ending in '.'. Ranges (positive radii, non-zero axes) are
// validate_scene's, shared with YAML.
SphereDesc convert(const v1::Sphere& in, const std::string& at, ProtoChecker& check) {
  SphereDesc s;
  s.center = check.vec3(at + "center", in.center());
  s.radius = check.number(at + "radius", in.radius());
  return s;
}
QuadDesc convert(const v1::Rectangle& in, const std::string& at, ProtoChecker& check) {
  QuadDesc q;
  q.corner = check.vec3(at + "corner", in.corner());
  q.u = check.vec3(at + "u", in.u());
  q.v = check.vec3(at + "v", in.v());
  return q;
}
PlaneDesc convert(const v1::Plane& in, const std::string& at, ProtoChecker& check) {
  PlaneDesc p;
  p.point = check.vec3(at + "point", in.point());
  p.normal = check.vec3(at + "normal", in.normal());
  return p;
}
DiskDesc convert(const v1::Disk& in, const std::string& at, ProtoChecker& check) {
  DiskDesc d;
  d.center = check.vec3(at + "center", in.center());
  d.normal = check.vec3(at + "normal", in.normal());
  d.radius = check.number(at + "radius", in.radius());
  d.inner_radius = check.number(at + "inner_radius", in.inner_radius());
  return d;
}
CylinderDesc convert(const v1::Cylinder& in, const std::string& at, ProtoChecker& check) {
  CylinderDesc c;
  c.base = check.vec3(at + "base", in.base());
  c.axis = check.vec3(at + "axis", in.axis());
  c.radius = check.number(at + "radius", in.radius());
  c.height = check.number(at + "height", in.height());
  c.caps = in.caps();
  return c;
}
ConeDesc convert(const v1::Cone& in, const std::string& at, ProtoChecker& check) {
  ConeDesc c;
  c.base = check.vec3(at + "base", in.base());
  c.axis = check.vec3(at + "axis", in.axis());
  c.base_radius = check.number(at + "base_radius", in.base_radius());
  c.top_radius = check.number(at + "top_radius", in.top_radius());
  c.height = check.number(at + "height", in.height());
  c.caps = in.caps();
  return c;
}
TorusDesc convert(const v1::Torus& in, const std::string& at, ProtoChecker& check) {
  TorusDesc t;
  t.center = check.vec3(at + "center", in.center());
  t.axis = check.vec3(at + "axis", in.axis());
  t.major_radius = check.number(at + "major_radius", in.major_radius());
  t.minor_radius = check.number(at + "minor_radius", in.minor_radius());
  return t;
}
std::vector<double> convert_numbers(const google::protobuf::RepeatedField<double>& in,
                                    const std::string& field, ProtoChecker& check) {
  std::vector<double> out(in.begin(), in.end());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i])) {
      check.number(indexed(field, i), out[i]);
      break;
    }
  return out;
}
SplinePatchDesc convert(const v1::SplinePatch& in, const std::string& at, ProtoChecker& check) {
  SplinePatchDesc p;
  p.count_u = in.count_u();
  p.count_v = in.count_v();
  const std::vector<double> xyz =
      convert_numbers(in.control_points(), at + "control_points", check);
  if (xyz.size() % 3 != 0)
    check.fail(at + "control_points",
               "must hold x, y, z of each point (a multiple of 3 values), got " +
                   std::to_string(xyz.size()));
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    p.control_points.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  p.weights = convert_numbers(in.weights(), at + "weights", check);
  p.knots_u = convert_numbers(in.knots_u(), at + "knots_u", check);
  p.knots_v = convert_numbers(in.knots_v(), at + "knots_v", check);
  return p;
}
TrimmedFaceDesc convert(const v1::TrimmedFace& in, const std::string& at, ProtoChecker& check) {
  TrimmedFaceDesc f;
  switch (in.surface_case()) {
    case v1::TrimmedFace::kPlane:
      f.surface = convert(in.plane(), at + "plane.", check);
      break;
    case v1::TrimmedFace::kDisk:
      f.surface = convert(in.disk(), at + "disk.", check);
      break;
    case v1::TrimmedFace::kRectangle:
      f.surface = convert(in.rectangle(), at + "rectangle.", check);
      break;
    case v1::TrimmedFace::kSphere:
      f.surface = convert(in.sphere(), at + "sphere.", check);
      break;
    case v1::TrimmedFace::kCylinder: {
      CylinderDesc c = convert(in.cylinder(), at + "cylinder.", check);
      c.caps = false;  // a face is the side only
      f.surface = c;
      break;
    }
    case v1::TrimmedFace::kCone: {
      ConeDesc c = convert(in.cone(), at + "cone.", check);
      c.caps = false;
      f.surface = c;
      break;
    }
    case v1::TrimmedFace::kTorus:
      f.surface = convert(in.torus(), at + "torus.", check);
      break;
    case v1::TrimmedFace::kPatch:
      f.surface = convert(in.patch(), at + "patch.", check);
      break;
    case v1::TrimmedFace::SURFACE_NOT_SET:
      check.fail(at + "surface",
                 "is required: set one of plane, disk, rectangle, sphere, cylinder, cone, torus "
                 "or patch");
      break;
  }
  for (int k = 0; k < in.loops_size(); ++k) {
    const std::string field = indexed(at + "loops", static_cast<std::size_t>(k));
    const std::vector<double> uv = convert_numbers(in.loops(k).uv(), field + ".uv", check);
    if (uv.size() % 2 != 0)
      check.fail(field + ".uv", "must hold u, v of each point (an even number of values), got " +
                                    std::to_string(uv.size()));
    std::vector<glm::dvec2>& loop = f.loops.emplace_back();
    for (std::size_t i = 0; i + 1 < uv.size(); i += 2) loop.emplace_back(uv[i], uv[i + 1]);
  }
  return f;
}

void convert_geometry(const v1::Scene& in, ProtoChecker& check, SceneDescription& scene) {
  for (int i = 0; i < in.geometry_size(); ++i) {
    const v1::Geometry& g = in.geometry(i);
    const auto index = static_cast<std::uint32_t>(i);
    const std::string path = indexed("geometry", index);

    std::uint32_t material = 0;
    if (g.material().empty()) {
      check.fail(path + ".material", "is required but missing");
    } else if (const auto found = scene.find_material(g.material())) {
      material = *found;
    } else {
      check.fail(path + ".material", "unknown material '" + g.material() + "'");
    }
    const bool visible = !g.has_visible() || g.visible();

    const std::optional<TransformDesc> transform = convert_transform(g, path, check);
    // Fills the fields every shape description has.
    const auto common = [&](auto& desc) {
      desc.material = material;
      desc.visible = visible;
      desc.source_index = index;
      desc.transform = transform;
    };
    switch (g.shape_case()) {
      case v1::Geometry::kSphere: {
        SphereDesc sphere = convert(g.sphere(), path + ".sphere.", check);
        if (std::isfinite(sphere.radius) && !(sphere.radius > 0.0))
          check.fail(path + ".sphere.radius",
                     "must be positive, got " + format_number(sphere.radius));
        common(sphere);
        scene.spheres.push_back(sphere);
        break;
      }
      case v1::Geometry::kRectangle: {
        QuadDesc q = convert(g.rectangle(), path + ".rectangle.", check);
        common(q);
        scene.quads.push_back(q);
        break;
      }
      case v1::Geometry::kTriangle: {
        TriangleMeshDesc mesh;
        mesh.positions = {check.vec3(path + ".triangle.v0", g.triangle().v0()),
                          check.vec3(path + ".triangle.v1", g.triangle().v1()),
                          check.vec3(path + ".triangle.v2", g.triangle().v2())};
        mesh.indices = {0, 1, 2};
        common(mesh);
        scene.meshes.push_back(std::move(mesh));
        break;
      }
      case v1::Geometry::kMesh: {
        TriangleMeshDesc mesh;
        convert_mesh(g.mesh(), path + ".mesh", check, mesh);
        common(mesh);
        scene.meshes.push_back(std::move(mesh));
        break;
      }
      case v1::Geometry::kPlane: {
        PlaneDesc p = convert(g.plane(), path + ".plane.", check);
        common(p);
        scene.planes.push_back(p);
        break;
      }
      case v1::Geometry::kDisk: {
        DiskDesc d = convert(g.disk(), path + ".disk.", check);
        common(d);
        scene.disks.push_back(d);
        break;
      }
      case v1::Geometry::kCylinder: {
        CylinderDesc c = convert(g.cylinder(), path + ".cylinder.", check);
        common(c);
        scene.cylinders.push_back(c);
        break;
      }
      case v1::Geometry::kCone: {
        ConeDesc c = convert(g.cone(), path + ".cone.", check);
        common(c);
        scene.cones.push_back(c);
        break;
      }
      case v1::Geometry::kTorus: {
        TorusDesc t = convert(g.torus(), path + ".torus.", check);
        common(t);
        scene.tori.push_back(t);
        break;
      }
      case v1::Geometry::kSplinePatch: {
        SplinePatchDesc p = convert(g.spline_patch(), path + ".spline_patch.", check);
        common(p);
        scene.patches.push_back(std::move(p));
        break;
      }
      case v1::Geometry::kTrimmedFace: {
        TrimmedFaceDesc f = convert(g.trimmed_face(), path + ".trimmed_face.", check);
        common(f);
        scene.trimmed_faces.push_back(std::move(f));
        break;
      }
      case v1::Geometry::kSdfBox: {
        const std::string at = path + ".sdf_box.";
        const v1::SdfBox& in = g.sdf_box();
        SdfBoxDesc b;
        b.center = check.vec3(at + "center", in.center());
        b.half_extent = check.vec3(at + "half_extent", in.half_extent());
        b.rounding = check.number(at + "rounding", in.rounding());
        common(b);
        scene.sdf_boxes.push_back(b);
        break;
      }
      case v1::Geometry::kSdfTorus: {
        const std::string at = path + ".sdf_torus.";
        const v1::SdfTorus& in = g.sdf_torus();
        SdfTorusDesc t;
        t.center = check.vec3(at + "center", in.center());
        t.axis = check.vec3(at + "axis", in.axis());
        t.major_radius = check.number(at + "major_radius", in.major_radius());
        t.minor_radius = check.number(at + "minor_radius", in.minor_radius());
        common(t);
        scene.sdf_tori.push_back(t);
        break;
      }
      case v1::Geometry::kSdfCapsule: {
        const std::string at = path + ".sdf_capsule.";
        const v1::SdfCapsule& in = g.sdf_capsule();
        SdfCapsuleDesc c;
        c.a = check.vec3(at + "a", in.a());
        c.b = check.vec3(at + "b", in.b());
        c.radius = check.number(at + "radius", in.radius());
        common(c);
        scene.sdf_capsules.push_back(c);
        break;
      }
      case v1::Geometry::SHAPE_NOT_SET:
        check.fail(path + ".shape",
                   "is required: set one of sphere, rectangle, triangle, mesh, plane, disk, "
                   "cylinder, cone, torus, sdf_box, sdf_torus, sdf_capsule, spline_patch or "
                   "trimmed_face");
        break;
    }
  }
}

// validate_scene() speaks the YAML loader's paths; rewrite them to the protobuf ones.
std::string proto_field(const std::string& core_field, const v1::Scene& scene) {
  static const std::pair<const char*, const char*> kRenamed[] = {
      {"camera.fov", "camera.fov_degrees"},
      {"settings.background_color", "background.color"},
      {"settings.background_intensity", "background.intensity"},
      {"render.spp", "settings.samples_per_pixel"},
  };
  for (const auto& [from, to] : kRenamed)
    if (core_field == from) return to;
  if (core_field.rfind("render.", 0) == 0) return "settings." + core_field.substr(7);

  constexpr std::string_view kGeometry = "geometry[";
  if (core_field.rfind(kGeometry, 0) != 0) return core_field;
  const auto close = core_field.find("].");
  if (close == std::string::npos) return core_field;
  const int index = std::stoi(core_field.substr(kGeometry.size(), close - kGeometry.size()));
  if (index < 0 || index >= scene.geometry_size()) return core_field;
  const std::string head = core_field.substr(0, close + 2);
  const std::string rest = core_field.substr(close + 2);
  // Fields of Geometry itself keep their path.
  if (rest.rfind("material", 0) == 0 || rest.rfind("visible", 0) == 0 ||
      rest.rfind("transform", 0) == 0)
    return core_field;
  switch (scene.geometry(index).shape_case()) {
    case v1::Geometry::kSphere:
      return head + "sphere." + rest;
    case v1::Geometry::kRectangle:
      return head + "rectangle." + rest;
    case v1::Geometry::kMesh:
      return head + "mesh." + rest;
    case v1::Geometry::kTriangle:
      // The triangle became a three-vertex mesh: positions[k] is vk.
      if (rest.rfind("positions[", 0) == 0 && rest.size() > 10)
        return head + "triangle.v" + rest.substr(10, 1) + rest.substr(rest.find(']') + 1);
      return head + "triangle";
    case v1::Geometry::kPlane:
      return head + "plane." + rest;
    case v1::Geometry::kDisk:
      return head + "disk." + rest;
    case v1::Geometry::kCylinder:
      return head + "cylinder." + rest;
    case v1::Geometry::kCone:
      return head + "cone." + rest;
    case v1::Geometry::kTorus:
      return head + "torus." + rest;
    case v1::Geometry::kSdfBox:
      return head + "sdf_box." + rest;
    case v1::Geometry::kSdfTorus:
      return head + "sdf_torus." + rest;
    case v1::Geometry::kSdfCapsule:
      return head + "sdf_capsule." + rest;
    case v1::Geometry::kSplinePatch:
      return head + "spline_patch." + rest;
    case v1::Geometry::kTrimmedFace: {
      // geometry[i].surface.x names the field x of the face's surface message.
      constexpr std::string_view kSurface = "surface.";
      if (rest.rfind(kSurface, 0) == 0) {
        static constexpr const char* kMessages[] = {"",           "plane.",  "disk.",
                                                    "rectangle.", "sphere.", "cylinder.",
                                                    "cone.",      "torus.",  "patch."};
        const int which = static_cast<int>(scene.geometry(index).trimmed_face().surface_case());
        return head + "trimmed_face." + kMessages[which] + rest.substr(kSurface.size());
      }
      return head + "trimmed_face." + rest;
    }
    case v1::Geometry::SHAPE_NOT_SET:
      break;
  }
  return core_field;
}

}  // namespace

RenderSettings settings_from_proto(const v1::RenderSettings& in) {
  RenderSettings out;
  out.width = in.width() != 0 ? in.width() : kDefaultWidth;
  out.height = in.height() != 0 ? in.height() : kDefaultHeight;
  out.samples_per_pixel =
      in.samples_per_pixel() != 0 ? in.samples_per_pixel() : kDefaultSamplesPerPixel;
  out.max_depth = in.max_depth() != 0 ? in.max_depth() : kDefaultMaxDepth;
  out.tile_size = in.tile_size() != 0 ? in.tile_size() : kDefaultTileSize;
  out.seed = in.seed();
  switch (in.integrator()) {
    case v1::INTEGRATOR_NORMALS:
      out.integrator = IntegratorKind::kNormals;
      break;
    case v1::INTEGRATOR_SHADOW:
      out.integrator = IntegratorKind::kShadow;
      break;
    case v1::INTEGRATOR_TRANSPARENCY:
      out.integrator = IntegratorKind::kTransparency;
      break;
    case v1::INTEGRATOR_ALBEDO:
      out.integrator = IntegratorKind::kAlbedo;
      break;
    case v1::INTEGRATOR_DEPTH:
      out.integrator = IntegratorKind::kDepth;
      break;
    default:
      out.integrator = IntegratorKind::kPath;
      break;  // unknown values are rejected in scene_from_proto
  }
  for (int aov : in.aovs())
    if (aov >= v1::AOV_ALBEDO && aov <= v1::AOV_PRIMITIVE_ID)
      out.aovs |= 1u << (aov - v1::AOV_ALBEDO);
  return out;
}

v1::RenderSettings settings_to_proto(const RenderSettings& in) {
  v1::RenderSettings out;
  out.set_width(in.width);
  out.set_height(in.height);
  out.set_samples_per_pixel(in.samples_per_pixel);
  out.set_max_depth(in.max_depth);
  out.set_tile_size(in.tile_size);
  out.set_seed(in.seed);
  out.set_integrator(
      static_cast<v1::Integrator>(static_cast<int>(in.integrator) + v1::INTEGRATOR_PATH));
  for (std::uint32_t i = 0; i < 4; ++i)
    if ((in.aovs & (1u << i)) != 0)
      out.add_aovs(static_cast<v1::Aov>(v1::AOV_ALBEDO + static_cast<int>(i)));
  return out;
}

SceneConversion scene_from_proto(const v1::Scene& in, const v1::RenderSettings& settings,
                                 const SceneLimits& limits) {
  SceneConversion result;
  ProtoChecker check(result.issues);
  SceneDescription scene;
  convert_camera(in, check, scene.camera);
  convert_background(in, check, scene.background);
  convert_materials(in, check, scene.materials);
  convert_geometry(in, check, scene);
  scene.render = settings_from_proto(settings);
  if (!v1::Integrator_IsValid(settings.integrator()))
    check.fail("settings.integrator",
               "unknown integrator value " + std::to_string(settings.integrator()));
  for (int i = 0; i < settings.aovs_size(); ++i)
    if (settings.aovs(i) < v1::AOV_ALBEDO || settings.aovs(i) > v1::AOV_PRIMITIVE_ID)
      check.fail("settings.aovs[" + std::to_string(i) + "]",
                 "unknown AOV value " + std::to_string(settings.aovs(i)));
  // The semantic checks assume a structurally sound scene (finite numbers, valid
  // references), so they run only once the structure is right.
  if (!result.issues.empty()) return result;

  for (SceneIssue issue : validate_scene(scene, limits)) {
    issue.field = proto_field(issue.field, in);
    result.issues.push_back(std::move(issue));
  }
  if (result.issues.empty()) result.scene = std::move(scene);
  return result;
}

std::string describe_issues(const std::vector<SceneIssue>& issues) {
  constexpr std::size_t kShown = 10;
  std::string text;
  for (std::size_t i = 0; i < issues.size() && i < kShown; ++i) {
    if (i > 0) text += "; ";
    text += issues[i].to_string();
  }
  if (issues.size() > kShown) text += "; and " + std::to_string(issues.size() - kShown) + " more";
  return text;
}

}  // namespace tessera::server
