#include "tessera/scene/yaml_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <map>
#include <sstream>

#include "tessera/scene/mesh_loader.hpp"

namespace tessera {
namespace {

// Walks the YAML tree with the current field path, so every error and warning can say
// where it is: file, line and the path the user wrote.
class YamlReader {
 public:
  YamlReader(std::string file, std::vector<SceneIssue>& warnings)
      : file_(std::move(file)), warnings_(warnings) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& message) const {
    throw SceneError(SceneIssue{file_, line_of(node), field, message});
  }
  void warn(const YAML::Node& node, const std::string& field, const std::string& message) const {
    warnings_.push_back(SceneIssue{file_, line_of(node), field, message});
  }
  static int line_of(const YAML::Node& node) {
    if (!node.IsDefined() || node.Mark().is_null()) return 0;
    return node.Mark().line + 1;
  }
  const std::string& file() const { return file_; }

  // Warns about keys of `map` not in `known`.
  void check_keys(const YAML::Node& map, const std::string& path,
                  std::initializer_list<const char*> known) const {
    for (const auto& entry : map) {
      const std::string key = entry.first.Scalar();
      bool found = false;
      for (const char* k : known)
        if (key == k) found = true;
      if (!found) warn(entry.first, join(path, key), "unknown key, ignored");
    }
  }
  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  double number(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, std::string("must be a number, got a ") + kind(node));
    double value = 0.0;
    if (!YAML::convert<double>::decode(node, value))
      fail(node, field, "must be a number, got '" + node.Scalar() + "'");
    if (!std::isfinite(value)) fail(node, field, "must be a finite number, got " + node.Scalar());
    return value;
  }
  std::uint32_t unsigned_int(const YAML::Node& node, const std::string& field) const {
    const double value = number(node, field);
    if (value < 0 || value != std::floor(value) || value > 4294967295.0)
      fail(node, field, "must be a non-negative integer, got " + node.Scalar());
    return static_cast<std::uint32_t>(value);
  }
  std::uint64_t seed(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, std::string("must be an integer, got a ") + kind(node));
    std::uint64_t value = 0;
    if (!YAML::convert<std::uint64_t>::decode(node, value))
      fail(node, field, "must be a non-negative integer, got '" + node.Scalar() + "'");
    return value;
  }
  bool boolean(const YAML::Node& node, const std::string& field) const {
    bool value = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
      fail(node, field,
           "must be true or false, got '" + (node.IsScalar() ? node.Scalar() : kind(node)) + "'");
    return value;
  }
  std::string string(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, std::string("must be a string, got a ") + kind(node));
    return node.Scalar();
  }
  glm::dvec3 vec3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3)
      fail(node, field,
           std::string("must be a list of three numbers, got ") +
               (node.IsSequence() ? std::to_string(node.size()) + " elements"
                                  : std::string("a ") + kind(node)));
    return glm::dvec3(number(node[0], field + "[0]"), number(node[1], field + "[1]"),
                      number(node[2], field + "[2]"));
  }
  // A colour may also be written as one number for grey.
  glm::dvec3 color(const YAML::Node& node, const std::string& field) const {
    if (node.IsScalar()) return glm::dvec3(number(node, field));
    return vec3(node, field);
  }
  YAML::Node required(const YAML::Node& map, const char* key, const std::string& path) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined() || node.IsNull()) fail(map, join(path, key), "is required but missing");
    return node;
  }
  static const char* kind(const YAML::Node& node) {
    switch (node.Type()) {
      case YAML::NodeType::Map:
        return "map";
      case YAML::NodeType::Sequence:
        return "list";
      case YAML::NodeType::Scalar:
        return "scalar";
      case YAML::NodeType::Null:
        return "null";
      default:
        return "missing value";
    }
  }

 private:
  std::string file_;
  std::vector<SceneIssue>& warnings_;
};

class SceneBuilder {
 public:
  SceneBuilder(YamlReader& reader, std::filesystem::path base_directory,
               const SceneLoadOptions& options)
      : in_(reader), base_directory_(std::move(base_directory)), options_(options) {}

  SceneDescription build(const YAML::Node& root) {
    if (!root.IsMap())
      in_.fail(root, "", "the scene must be a YAML map with camera, materials and geometry");
    in_.check_keys(root, "",
                   {"camera", "settings", "materials", "geometry", "geometries", "render"});
    if (root["camera"]) read_camera(root["camera"]);
    if (root["settings"]) read_settings(root["settings"]);
    if (root["materials"]) read_materials(root["materials"]);
    const char* geometry_key = root["geometry"] ? "geometry" : "geometries";  // RayON accepts both
    if (root["geometry"] && root["geometries"])
      in_.fail(root["geometries"], "geometries", "give either geometry or geometries, not both");
    if (root[geometry_key]) read_geometry(root[geometry_key], geometry_key);
    if (root["render"]) read_render(root["render"]);
    return std::move(scene_);
  }

  // Field path -> YAML node, for the line numbers of semantic errors found after parsing.
  const std::map<std::string, YAML::Node>& locations() const { return locations_; }
  std::size_t mesh_files_read() const { return mesh_cache_.size(); }

 private:
  YAML::Node map_at(const YAML::Node& node, const std::string& path) {
    if (!node.IsMap())
      in_.fail(node, path, std::string("must be a map, got a ") + YamlReader::kind(node));
    locations_[path] = node;
    return node;
  }
  template <typename Fn>
  void optional(const YAML::Node& map, const char* key, const std::string& path, Fn&& read) {
    const YAML::Node node = map[key];
    if (!node.IsDefined()) return;
    const std::string field = YamlReader::join(path, key);
    locations_[field] = node;
    read(node, field);
  }

  void read_camera(const YAML::Node& node) {
    map_at(node, "camera");
    in_.check_keys(node, "camera", {"position", "look_at", "up", "fov"});
    auto& cam = scene_.camera;
    optional(node, "position", "camera", [&](auto& n, auto& f) { cam.position = in_.vec3(n, f); });
    optional(node, "look_at", "camera", [&](auto& n, auto& f) { cam.look_at = in_.vec3(n, f); });
    optional(node, "up", "camera", [&](auto& n, auto& f) { cam.up = in_.vec3(n, f); });
    optional(node, "fov", "camera", [&](auto& n, auto& f) { cam.fov_degrees = in_.number(n, f); });
  }

  void read_settings(const YAML::Node& node) {
    map_at(node, "settings");
    in_.check_keys(node, "settings",
                   {"background_color", "background_intensity", "ambient_light", "use_bvh",
                    "adaptive_sampling"});
    auto& bg = scene_.background;
    optional(node, "background_color", "settings",
             [&](auto& n, auto& f) { bg.color = in_.color(n, f); });
    optional(node, "background_intensity", "settings",
             [&](auto& n, auto& f) { bg.intensity = in_.number(n, f); });
    optional(node, "ambient_light", "settings", [&](auto& n, auto& f) {
      if (in_.number(n, f) != 0.0) in_.warn(n, f, "RayON's ambient term is not supported; ignored");
    });
    // RayON renderer switches; Tessera always picks its own acceleration and sampling.
    optional(node, "use_bvh", "settings", [&](auto& n, auto& f) { in_.boolean(n, f); });
    optional(node, "adaptive_sampling", "settings", [&](auto& n, auto& f) { in_.boolean(n, f); });
  }

  void read_materials(const YAML::Node& node) {
    if (!node.IsSequence())
      in_.fail(node, "materials", std::string("must be a list, got a ") + YamlReader::kind(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "materials[" + std::to_string(i) + "]";
      const YAML::Node m = map_at(node[i], path);
      in_.check_keys(
          m, path,
          {"name", "type", "albedo", "emission", "roughness", "refractive_index", "metallic",
           "transmission", "anisotropy", "preset", "film_thickness", "film_ior"});
      MaterialDesc mat;
      mat.name = in_.string(in_.required(m, "name", path), path + ".name");
      const std::string type_field = path + ".type";
      const std::string type = in_.string(in_.required(m, "type", path), type_field);
      const auto parsed = material_type_from_string(type);
      if (!parsed)
        in_.fail(m["type"], type_field,
                 "unknown material type '" + type +
                     "' (expected lambertian, light, metal, rough_mirror, glass, "
                     "anisotropic_metal, clear_coat or "
                     "thin_film)");
      mat.type = *parsed;
      if (mat.type == MaterialType::kLight) mat.albedo = glm::dvec3(1.0);
      optional(m, "albedo", path, [&](auto& n, auto& f) { mat.albedo = in_.color(n, f); });
      optional(m, "emission", path, [&](auto& n, auto& f) { mat.emission = in_.color(n, f); });
      optional(m, "roughness", path, [&](auto& n, auto& f) { mat.roughness = in_.number(n, f); });
      optional(m, "refractive_index", path,
               [&](auto& n, auto& f) { mat.refractive_index = in_.number(n, f); });
      optional(m, "metallic", path, [&](auto& n, auto& f) { mat.metallic = in_.number(n, f); });
      optional(m, "transmission", path,
               [&](auto& n, auto& f) { mat.transmission = in_.number(n, f); });
      optional(m, "anisotropy", path, [&](auto& n, auto& f) { mat.anisotropy = in_.number(n, f); });
      optional(m, "preset", path, [&](auto& n, auto& f) { mat.preset = in_.string(n, f); });
      optional(m, "film_thickness", path,
               [&](auto& n, auto& f) { mat.film_thickness = in_.number(n, f); });
      optional(m, "film_ior", path, [&](auto& n, auto& f) { mat.film_ior = in_.number(n, f); });
      if (mat.type == MaterialType::kLight && !m["emission"])
        in_.fail(m, path + ".emission", "is required for a light material");
      if (scene_.find_material(mat.name))
        in_.fail(m["name"], path + ".name", "duplicate material name '" + mat.name + "'");
      scene_.materials.push_back(std::move(mat));
    }
  }

  std::uint32_t material_ref(const YAML::Node& g, const std::string& path) {
    const std::string field = path + ".material";
    const YAML::Node node = in_.required(g, "material", path);
    const std::string name = in_.string(node, field);
    const auto index = scene_.find_material(name);
    if (!index) in_.fail(node, field, "unknown material '" + name + "'");
    return *index;
  }

  // A number the semantic checks may complain about later: its node is remembered so the
  // error carries its line.
  double number_at(const YAML::Node& g, const char* key, const std::string& path) {
    const std::string field = YamlReader::join(path, key);
    const YAML::Node node = in_.required(g, key, path);
    locations_[field] = node;
    return in_.number(node, field);
  }
  double number_or(const YAML::Node& g, const char* key, const std::string& path, double fallback) {
    double value = fallback;
    optional(g, key, path, [&](auto& n, auto& f) { value = in_.number(n, f); });
    return value;
  }
  glm::dvec3 vec3_at(const YAML::Node& g, const char* key, const std::string& path) {
    const std::string field = YamlReader::join(path, key);
    const YAML::Node node = in_.required(g, key, path);
    locations_[field] = node;
    return in_.vec3(node, field);
  }
  glm::dvec3 vec3_or(const YAML::Node& g, const char* key, const std::string& path,
                     const glm::dvec3& fallback) {
    glm::dvec3 value = fallback;
    optional(g, key, path, [&](auto& n, auto& f) { value = in_.vec3(n, f); });
    return value;
  }
  bool bool_or(const YAML::Node& g, const char* key, const std::string& path, bool fallback) {
    bool value = fallback;
    optional(g, key, path, [&](auto& n, auto& f) { value = in_.boolean(n, f); });
    return value;
  }
  // A scale: one number (uniform) or three.
  glm::dvec3 scale_of(const YAML::Node& n, const std::string& f) {
    return n.IsScalar() ? glm::dvec3(in_.number(n, f)) : in_.vec3(n, f);
  }

  // transform: { translate: [x, y, z], rotate: { axis: [x, y, z], degrees: a }, scale: s }
  std::optional<TransformDesc> read_transform(const YAML::Node& g, const std::string& path) {
    std::optional<TransformDesc> result;
    optional(g, "transform", path, [&](const YAML::Node& n, const std::string& f) {
      map_at(n, f);
      in_.check_keys(n, f, {"translate", "rotate", "scale"});
      TransformDesc t;
      optional(n, "translate", f, [&](auto& v, auto& vf) { t.translate = in_.vec3(v, vf); });
      optional(n, "rotate", f, [&](const YAML::Node& r, const std::string& rf) {
        map_at(r, rf);
        in_.check_keys(r, rf, {"axis", "degrees"});
        t.rotate_axis = vec3_at(r, "axis", rf);
        t.rotate_degrees = number_at(r, "degrees", rf);
      });
      optional(n, "scale", f, [&](auto& v, auto& vf) { t.scale = scale_of(v, vf); });
      result = t;
    });
    return result;
  }

  // Fills the fields every shape description has.
  template <typename Desc>
  void common(Desc& desc, const YAML::Node& g, const std::string& path, std::uint32_t index,
              bool visible) {
    desc.material = material_ref(g, path);
    desc.visible = visible;
    desc.source_index = index;
    desc.transform = read_transform(g, path);
  }

  void read_geometry(const YAML::Node& node, const char* key) {
    if (!node.IsSequence())
      in_.fail(node, key, std::string("must be a list, got a ") + YamlReader::kind(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "geometry[" + std::to_string(i) + "]";
      const YAML::Node g = map_at(node[i], path);
      const std::string type = in_.string(in_.required(g, "type", path), path + ".type");
      const auto index = static_cast<std::uint32_t>(i);
      bool visible = true;
      optional(g, "visible", path, [&](auto& n, auto& f) { visible = in_.boolean(n, f); });
      if (type == "sphere") {
        in_.check_keys(g, path, {"type", "material", "center", "radius", "visible", "transform"});
        SphereDesc s = sphere_fields(g, path);
        common(s, g, path, index, visible);
        scene_.spheres.push_back(s);
      } else if (type == "rectangle" || type == "quad") {
        in_.check_keys(g, path, {"type", "material", "corner", "u", "v", "visible", "transform"});
        QuadDesc q = quad_fields(g, path);
        common(q, g, path, index, visible);
        scene_.quads.push_back(q);
      } else if (type == "triangle") {
        in_.check_keys(g, path, {"type", "material", "v0", "v1", "v2", "visible", "transform"});
        TriangleMeshDesc mesh;
        common(mesh, g, path, index, visible);
        mesh.positions = {in_.vec3(in_.required(g, "v0", path), path + ".v0"),
                          in_.vec3(in_.required(g, "v1", path), path + ".v1"),
                          in_.vec3(in_.required(g, "v2", path), path + ".v2")};
        mesh.indices = {0, 1, 2};
        scene_.meshes.push_back(std::move(mesh));
      } else if (type == "obj" || type == "mesh") {
        in_.check_keys(g, path,
                       {"type", "material", "file", "position", "scale", "visible", "transform"});
        const std::uint32_t material = material_ref(g, path);
        const YAML::Node file_node = in_.required(g, "file", path);
        const std::string file = in_.string(file_node, path + ".file");
        // RayON's placement (scale, then move) becomes the entry's transform (composed
        // under an explicit one), so that entries placing one file keep identical vertices
        // and the renderer can share them (prepared_scene.cpp).
        TransformDesc placement;
        optional(g, "position", path,
                 [&](auto& n, auto& f) { placement.translate = in_.vec3(n, f); });
        optional(g, "scale", path, [&](auto& n, auto& f) {
          placement.scale = scale_of(n, f);
          if (placement.scale.x == 0.0 || placement.scale.y == 0.0 || placement.scale.z == 0.0)
            in_.fail(n, f, "components must not be zero");
        });
        TriangleMeshDesc mesh = load_mesh(file_node, path + ".file", file);
        mesh.material = material;
        mesh.visible = visible;
        mesh.source_index = index;
        mesh.transform = read_transform(g, path);
        if (placement != TransformDesc{}) {
          if (!mesh.transform) {
            mesh.transform = placement;
          } else {
            // T * translate(p) * scale(s) = translate(T(p)) * R * (S_T * s): still one
            // translate-rotate-scale, because the two diagonal scales commute.
            TransformDesc& t = *mesh.transform;
            t.translate = glm::dvec3(t.matrix() * glm::dvec4(placement.translate, 1.0));
            t.scale *= placement.scale;
          }
        }
        scene_.meshes.push_back(std::move(mesh));
      } else if (type == "plane") {
        in_.check_keys(g, path, {"type", "material", "point", "normal", "visible", "transform"});
        PlaneDesc p = plane_fields(g, path);
        common(p, g, path, index, visible);
        scene_.planes.push_back(p);
      } else if (type == "disk") {
        in_.check_keys(g, path,
                       {"type", "material", "center", "normal", "radius", "inner_radius", "visible",
                        "transform"});
        DiskDesc d = disk_fields(g, path);
        common(d, g, path, index, visible);
        scene_.disks.push_back(d);
      } else if (type == "cylinder") {
        in_.check_keys(g, path,
                       {"type", "material", "base", "axis", "radius", "height", "caps", "visible",
                        "transform"});
        CylinderDesc c = cylinder_fields(g, path);
        common(c, g, path, index, visible);
        scene_.cylinders.push_back(c);
      } else if (type == "cone") {
        in_.check_keys(g, path,
                       {"type", "material", "base", "axis", "base_radius", "top_radius", "height",
                        "caps", "visible", "transform"});
        ConeDesc c = cone_fields(g, path);
        common(c, g, path, index, visible);
        scene_.cones.push_back(c);
      } else if (type == "torus" || type == "sdf_torus") {
        in_.check_keys(g, path,
                       {"type", "material", "center", "axis", "major_radius", "minor_radius",
                        "visible", "transform"});
        TorusDesc t = torus_fields(g, path);
        common(t, g, path, index, visible);
        if (type == "torus") {
          scene_.tori.push_back(t);
        } else {
          scene_.sdf_tori.push_back(SdfTorusDesc{t.center, t.axis, t.major_radius, t.minor_radius,
                                                 t.material, t.visible, t.source_index,
                                                 t.transform});
        }
      } else if (type == "sdf_box" || type == "sdf_rounded_box") {
        const bool rounded = type == "sdf_rounded_box";
        if (rounded)
          in_.check_keys(
              g, path,
              {"type", "material", "center", "half_extent", "rounding", "visible", "transform"});
        else
          in_.check_keys(g, path,
                         {"type", "material", "center", "half_extent", "visible", "transform"});
        SdfBoxDesc b;
        common(b, g, path, index, visible);
        b.center = vec3_or(g, "center", path, glm::dvec3(0.0));
        b.half_extent = vec3_at(g, "half_extent", path);
        if (rounded) b.rounding = number_at(g, "rounding", path);
        scene_.sdf_boxes.push_back(b);
      } else if (type == "sdf_capsule") {
        in_.check_keys(g, path, {"type", "material", "a", "b", "radius", "visible", "transform"});
        SdfCapsuleDesc c;
        common(c, g, path, index, visible);
        c.a = vec3_at(g, "a", path);
        c.b = vec3_at(g, "b", path);
        c.radius = number_at(g, "radius", path);
        scene_.sdf_capsules.push_back(c);
      } else if (type == "bspline_patch") {
        in_.check_keys(g, path,
                       {"type", "material", "control_points", "weights", "knots_u", "knots_v",
                        "visible", "transform"});
        SplinePatchDesc p = patch_fields(g, path);
        common(p, g, path, index, visible);
        scene_.patches.push_back(std::move(p));
      } else if (type == "trimmed") {
        in_.check_keys(g, path, {"type", "material", "surface", "loops", "visible", "transform"});
        TrimmedFaceDesc f;
        common(f, g, path, index, visible);
        f.surface = surface_fields(g, path);
        f.loops = loops_field(g, path);
        scene_.trimmed_faces.push_back(std::move(f));
      } else {
        in_.fail(g["type"], path + ".type",
                 "unknown geometry type '" + type +
                     "' (expected sphere, rectangle, quad, triangle, obj, mesh, plane, disk, "
                     "cylinder, cone, torus, sdf_box, sdf_rounded_box, sdf_torus, sdf_capsule, "
                     "bspline_patch or trimmed)");
      }
    }
  }

  // The shape fields of each type (material, visible and transform are common()'s), shared
  // by top-level entries and the `surface` of a trimmed face.
  SphereDesc sphere_fields(const YAML::Node& g, const std::string& path) {
    SphereDesc s;
    s.center = in_.vec3(in_.required(g, "center", path), path + ".center");
    s.radius = in_.number(in_.required(g, "radius", path), path + ".radius");
    locations_[path + ".radius"] = g["radius"];
    if (!(s.radius > 0.0))
      in_.fail(g["radius"], path + ".radius", "must be positive, got " + g["radius"].Scalar());
    return s;
  }
  QuadDesc quad_fields(const YAML::Node& g, const std::string& path) {
    QuadDesc q;
    q.corner = in_.vec3(in_.required(g, "corner", path), path + ".corner");
    q.u = in_.vec3(in_.required(g, "u", path), path + ".u");
    q.v = in_.vec3(in_.required(g, "v", path), path + ".v");
    locations_[path + ".v"] = g["v"];
    return q;
  }
  PlaneDesc plane_fields(const YAML::Node& g, const std::string& path) {
    PlaneDesc p;
    p.point = vec3_or(g, "point", path, glm::dvec3(0.0));
    p.normal = vec3_at(g, "normal", path);
    return p;
  }
  DiskDesc disk_fields(const YAML::Node& g, const std::string& path) {
    DiskDesc d;
    d.center = vec3_at(g, "center", path);
    d.normal = vec3_at(g, "normal", path);
    d.radius = number_at(g, "radius", path);
    d.inner_radius = number_or(g, "inner_radius", path, 0.0);
    return d;
  }
  CylinderDesc cylinder_fields(const YAML::Node& g, const std::string& path) {
    CylinderDesc c;
    c.base = vec3_at(g, "base", path);
    c.axis = vec3_or(g, "axis", path, glm::dvec3(0.0, 1.0, 0.0));
    c.radius = number_at(g, "radius", path);
    c.height = number_at(g, "height", path);
    c.caps = bool_or(g, "caps", path, false);
    return c;
  }
  ConeDesc cone_fields(const YAML::Node& g, const std::string& path) {
    ConeDesc c;
    c.base = vec3_at(g, "base", path);
    c.axis = vec3_or(g, "axis", path, glm::dvec3(0.0, 1.0, 0.0));
    c.base_radius = number_at(g, "base_radius", path);
    c.top_radius = number_or(g, "top_radius", path, 0.0);
    c.height = number_at(g, "height", path);
    c.caps = bool_or(g, "caps", path, false);
    return c;
  }
  TorusDesc torus_fields(const YAML::Node& g, const std::string& path) {
    TorusDesc t;
    t.center = vec3_at(g, "center", path);
    t.axis = vec3_or(g, "axis", path, glm::dvec3(0.0, 1.0, 0.0));
    t.major_radius = number_at(g, "major_radius", path);
    t.minor_radius = number_at(g, "minor_radius", path);
    return t;
  }

  // A list of numbers; each element's node is remembered for the semantic checks' lines.
  std::vector<double> number_list(const YAML::Node& n, const std::string& f) {
    if (!n.IsSequence())
      in_.fail(n, f, std::string("must be a list of numbers, got a ") + YamlReader::kind(n));
    locations_[f] = n;
    std::vector<double> values;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const std::string item = f + "[" + std::to_string(i) + "]";
      locations_[item] = n[i];
      values.push_back(in_.number(n[i], item));
    }
    return values;
  }

  // control_points: one row per u index, each row the count_v points along v.
  // weights (optional): the same shape, one number per point.
  SplinePatchDesc patch_fields(const YAML::Node& g, const std::string& path) {
    SplinePatchDesc p;
    const std::string rows_field = path + ".control_points";
    const YAML::Node rows = in_.required(g, "control_points", path);
    locations_[rows_field] = rows;
    if (!rows.IsSequence() || rows.size() < 4)
      in_.fail(rows, rows_field,
               "must be a list of at least 4 rows (u direction) of control points");
    p.count_u = static_cast<std::uint32_t>(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string row_field = rows_field + "[" + std::to_string(i) + "]";
      const YAML::Node row = rows[i];
      if (!row.IsSequence() || row.size() < 4)
        in_.fail(row, row_field, "must be a list of at least 4 points (v direction)");
      if (i == 0) p.count_v = static_cast<std::uint32_t>(row.size());
      if (row.size() != p.count_v)
        in_.fail(row, row_field,
                 "every row must have as many points as the first (" + std::to_string(p.count_v) +
                     "), got " + std::to_string(row.size()));
      for (std::size_t j = 0; j < row.size(); ++j) {
        const std::string point_field = row_field + "[" + std::to_string(j) + "]";
        locations_[rows_field + "[" + std::to_string(i * p.count_v + j) + "]"] = row[j];
        p.control_points.push_back(in_.vec3(row[j], point_field));
      }
    }
    optional(g, "weights", path, [&](const YAML::Node& n, const std::string& f) {
      if (!n.IsSequence() || n.size() != p.count_u)
        in_.fail(n, f,
                 "must be a list of " + std::to_string(p.count_u) +
                     " rows of weights, shaped like control_points");
      for (std::size_t i = 0; i < n.size(); ++i) {
        const std::string row_field = f + "[" + std::to_string(i) + "]";
        if (!n[i].IsSequence() || n[i].size() != p.count_v)
          in_.fail(n[i], row_field, "must be a list of " + std::to_string(p.count_v) + " weights");
        for (std::size_t j = 0; j < n[i].size(); ++j) {
          locations_[f + "[" + std::to_string(i * p.count_v + j) + "]"] = n[i][j];
          p.weights.push_back(in_.number(n[i][j], row_field + "[" + std::to_string(j) + "]"));
        }
      }
    });
    optional(g, "knots_u", path, [&](auto& n, auto& f) { p.knots_u = number_list(n, f); });
    optional(g, "knots_v", path, [&](auto& n, auto& f) { p.knots_v = number_list(n, f); });
    return p;
  }

  // surface: { type: sphere, center: ..., radius: ... } (any analytic surface or a patch,
  // without material, visible or transform: the face's apply).
  TrimmedSurfaceDesc surface_fields(const YAML::Node& g, const std::string& face_path) {
    const std::string path = face_path + ".surface";
    const YAML::Node s = map_at(in_.required(g, "surface", face_path), path);
    locations_[path] = s;
    const std::string type = in_.string(in_.required(s, "type", path), path + ".type");
    if (type == "sphere") {
      in_.check_keys(s, path, {"type", "center", "radius"});
      return sphere_fields(s, path);
    } else if (type == "rectangle" || type == "quad") {
      in_.check_keys(s, path, {"type", "corner", "u", "v"});
      return quad_fields(s, path);
    } else if (type == "plane") {
      in_.check_keys(s, path, {"type", "point", "normal"});
      return plane_fields(s, path);
    } else if (type == "disk") {
      in_.check_keys(s, path, {"type", "center", "normal", "radius", "inner_radius"});
      return disk_fields(s, path);
    } else if (type == "cylinder") {
      in_.check_keys(s, path, {"type", "base", "axis", "radius", "height"});
      return cylinder_fields(s, path);
    } else if (type == "cone") {
      in_.check_keys(s, path, {"type", "base", "axis", "base_radius", "top_radius", "height"});
      return cone_fields(s, path);
    } else if (type == "torus") {
      in_.check_keys(s, path, {"type", "center", "axis", "major_radius", "minor_radius"});
      return torus_fields(s, path);
    } else if (type == "bspline_patch") {
      in_.check_keys(s, path, {"type", "control_points", "weights", "knots_u", "knots_v"});
      return patch_fields(s, path);
    }
    in_.fail(s["type"], path + ".type",
             "unknown surface type '" + type +
                 "' for a trimmed face (expected plane, disk, rectangle, quad, sphere, cylinder, "
                 "cone, torus or bspline_patch)");
  }

  // loops: [[[u, v], ...], ...]: the outer loop, then holes.
  std::vector<std::vector<glm::dvec2>> loops_field(const YAML::Node& g, const std::string& path) {
    const std::string field = path + ".loops";
    const YAML::Node n = in_.required(g, "loops", path);
    locations_[field] = n;
    if (!n.IsSequence() || n.size() == 0)
      in_.fail(n, field, "must be a list of loops (the outer loop first, then holes)");
    std::vector<std::vector<glm::dvec2>> loops;
    for (std::size_t k = 0; k < n.size(); ++k) {
      const std::string loop_field = field + "[" + std::to_string(k) + "]";
      const YAML::Node loop = n[k];
      locations_[loop_field] = loop;
      if (!loop.IsSequence()) in_.fail(loop, loop_field, "must be a list of [u, v] points");
      std::vector<glm::dvec2>& points = loops.emplace_back();
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const std::string point_field = loop_field + "[" + std::to_string(i) + "]";
        const YAML::Node uv = loop[i];
        locations_[point_field] = uv;
        if (!uv.IsSequence() || uv.size() != 2)
          in_.fail(uv, point_field, "must be a [u, v] pair of numbers");
        points.emplace_back(in_.number(uv[0], point_field + "[0]"),
                            in_.number(uv[1], point_field + "[1]"));
      }
    }
    return loops;
  }

  TriangleMeshDesc load_mesh(const YAML::Node& node, const std::string& field,
                             const std::string& file) {
    std::filesystem::path path(file);
    if (path.is_relative()) path = base_directory_ / path;
    if (!options_.allowed_roots.empty() && !path_is_within(path, options_.allowed_roots))
      in_.fail(node, field, "'" + file + "' is outside the directories this server may read");
    // Each file is parsed once per scene: entries that place it again copy the cached mesh
    // (the renderer then shares one structure between them, prepared_scene.cpp).
    std::error_code ec;
    std::filesystem::path key = std::filesystem::weakly_canonical(path, ec);
    if (ec) key = path.lexically_normal();
    if (const auto cached = mesh_cache_.find(key.string()); cached != mesh_cache_.end())
      return cached->second;
    try {
      return mesh_cache_.emplace(key.string(), load_mesh_file(path)).first->second;
    } catch (const SceneError& e) {
      in_.fail(node, field,
               "cannot load mesh '" + path.lexically_normal().string() + "': " + e.issue().message);
    }
  }

  void read_render(const YAML::Node& node) {
    map_at(node, "render");
    in_.check_keys(
        node, "render",
        {"width", "height", "spp", "max_depth", "tile_size", "seed", "integrator", "aovs"});
    auto& r = scene_.render;
    optional(node, "width", "render", [&](auto& n, auto& f) { r.width = in_.unsigned_int(n, f); });
    optional(node, "height", "render",
             [&](auto& n, auto& f) { r.height = in_.unsigned_int(n, f); });
    optional(node, "spp", "render",
             [&](auto& n, auto& f) { r.samples_per_pixel = in_.unsigned_int(n, f); });
    optional(node, "max_depth", "render",
             [&](auto& n, auto& f) { r.max_depth = in_.unsigned_int(n, f); });
    optional(node, "tile_size", "render",
             [&](auto& n, auto& f) { r.tile_size = in_.unsigned_int(n, f); });
    optional(node, "seed", "render", [&](auto& n, auto& f) { r.seed = in_.seed(n, f); });
    optional(node, "integrator", "render", [&](auto& n, auto& f) {
      const std::string name = in_.string(n, f);
      const auto kind = integrator_from_string(name);
      if (!kind)
        in_.fail(n, f,
                 "unknown integrator '" + name +
                     "' (expected path, normals, shadow, transparency, albedo or depth)");
      r.integrator = *kind;
    });
    optional(node, "aovs", "render", [&](auto& n, auto& f) {
      if (!n.IsSequence())
        in_.fail(n, f, "must be a list of AOV names (albedo, normal, depth, primitive_id)");
      for (std::size_t i = 0; i < n.size(); ++i) {
        const std::string item = f + "[" + std::to_string(i) + "]";
        const std::string name = in_.string(n[i], item);
        const auto bit = aov_from_string(name);
        if (!bit)
          in_.fail(n[i], item,
                   "unknown AOV '" + name + "' (expected albedo, normal, depth or primitive_id)");
        r.aovs |= *bit;
      }
    });
  }

  YamlReader& in_;
  std::filesystem::path base_directory_;
  const SceneLoadOptions& options_;
  SceneDescription scene_;
  std::map<std::string, YAML::Node> locations_;
  std::map<std::string, TriangleMeshDesc> mesh_cache_;  // by canonical path
};

// The deepest recorded YAML node whose path is a prefix of `field`.
int line_for_field(const std::map<std::string, YAML::Node>& locations, const std::string& field) {
  std::string key = field;
  while (!key.empty()) {
    const auto it = locations.find(key);
    if (it != locations.end()) return YamlReader::line_of(it->second);
    const auto cut = key.find_last_of(".[");
    if (cut == std::string::npos) break;
    key.resize(cut);
  }
  return 0;
}

}  // namespace

LoadedScene load_scene_yaml(std::string_view text, const std::string& display_name,
                            const std::filesystem::path& base_directory,
                            const SceneLoadOptions& options) {
  LoadedScene result;
  YamlReader reader(display_name, result.warnings);
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw SceneError(SceneIssue{display_name, e.mark.is_null() ? 0 : e.mark.line + 1, "",
                                "YAML syntax error: " + e.msg});
  }
  if (!root.IsDefined() || root.IsNull())
    throw SceneError(SceneIssue{display_name, 0, "", "the scene file is empty"});
  SceneBuilder builder(reader, base_directory, options);
  try {
    result.scene = builder.build(root);
    result.mesh_files_read = builder.mesh_files_read();
  } catch (const YAML::Exception& e) {  // conversions inside yaml-cpp
    throw SceneError(SceneIssue{display_name, e.mark.is_null() ? 0 : e.mark.line + 1, "", e.msg});
  }
  // Top-level keys are checked before the sections they hold; report in file order.
  std::stable_sort(result.warnings.begin(), result.warnings.end(),
                   [](const SceneIssue& a, const SceneIssue& b) { return a.line < b.line; });
  const auto issues = validate_scene(result.scene, options.limits);
  if (!issues.empty()) {
    SceneIssue first = issues.front();
    first.file = display_name;
    first.line = line_for_field(builder.locations(), first.field);
    throw SceneError(first);
  }
  return result;
}

LoadedScene load_scene_file(const std::filesystem::path& path, const SceneLoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw SceneError(SceneIssue{path.string(), 0, "", "scene file not found"});
  if (!std::filesystem::is_regular_file(path, ec))
    throw SceneError(SceneIssue{path.string(), 0, "", "not a regular file"});
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(SceneIssue{path.string(), 0, "", "cannot open scene file"});
  std::ostringstream text;
  text << in.rdbuf();
  return load_scene_yaml(text.str(), path.string(), path.parent_path(), options);
}

}  // namespace tessera
