#include "tessera/scene/yaml_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <map>
#include <span>
#include <sstream>
#include <unordered_map>

#include "tessera/image/rgb_image.hpp"
#include "tessera/scene/mesh_loader.hpp"
#include "tessera/scene/schema/kinds.hpp"
#include "tessera/scene/schema/suggest.hpp"

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

  // Keys of `map` that `known` does not list are errors naming the key and the closest known
  // one (warnings with `lenient`); keys in `ignored` are RayON's, read and not used: a
  // warning says so.
  void check_keys(const YAML::Node& map, const std::string& path,
                  std::span<const std::string_view> known,
                  std::span<const schema::IgnoredKey> ignored = {}) const {
    for (const auto& entry : map) {
      const std::string key = entry.first.Scalar();
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      const auto rayon = std::find_if(ignored.begin(), ignored.end(),
                                      [&](const schema::IgnoredKey& k) { return k.name == key; });
      if (rayon != ignored.end()) {
        warn(entry.first, join(path, key),
             "RayON key read but not used: " + std::string(rayon->reason));
        continue;
      }
      const std::string message = "unknown key '" + key + "'" + schema::did_you_mean(key, known);
      if (!lenient_) fail(entry.first, join(path, key), message);
      warn(entry.first, join(path, key), message + ", ignored");
    }
  }
  void set_lenient(bool lenient) { lenient_ = lenient; }
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
    if (!node.IsDefined() || node.IsNull()) {
      // Under --lenient a misspelling was only warned about: name it here too.
      std::string hint;
      const std::string_view wanted[] = {key};
      if (map.IsMap())
        for (const auto& entry : map)
          if (entry.first.Scalar() != key &&
              !schema::closest_match(entry.first.Scalar(), wanted).empty())
            hint = " (is '" + entry.first.Scalar() + "' a misspelling of it?)";
      fail(map, join(path, key), "is required but missing" + hint);
    }
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
  bool lenient_ = false;
};

// The YAML keys of a kind's declared fields (their RayON spelling where it differs).
template <typename Fields>
std::vector<std::string_view> yaml_keys(const Fields& fields,
                                        std::initializer_list<std::string_view> extra = {}) {
  std::vector<std::string_view> keys(extra);
  for (const auto& field : fields)
    if (field.on_yaml()) keys.push_back(field.key(true));
  return keys;
}

class SceneBuilder {
 public:
  SceneBuilder(YamlReader& reader, std::filesystem::path base_directory,
               const SceneLoadOptions& options)
      : in_(reader), base_directory_(std::move(base_directory)), options_(options) {}

  SceneDescription build(const YAML::Node& root) {
    if (!root.IsMap())
      in_.fail(root, "", "the scene must be a YAML map with camera, materials and geometry");
    static constexpr std::string_view kSections[] = {"camera",   "settings", "environment",
                                                     "lights",   "textures", "materials",
                                                     "geometry", "render",   "geometries"};
    in_.check_keys(root, "", kSections);
    if (root["camera"]) section<schema::CameraKind>(root["camera"], scene_.camera);
    if (root["settings"]) section<schema::BackgroundKind>(root["settings"], scene_.background);
    if (root["environment"]) {
      EnvironmentDesc& env = scene_.environment.emplace();
      section<schema::EnvironmentKind>(root["environment"], env);
      if (env.type == "image") load_environment_image(root["environment"], env);
    } else if (root["settings"]) {
      // RayON's settings: its renderer draws a sky gradient times background_intensity
      // and does not use background_color, so its scenes render that way here too.
      scene_.environment =
          EnvironmentDesc{"gradient", glm::dvec3(1.0), scene_.background.intensity};
    }
    if (root["lights"]) read_lights(root["lights"]);
    if (root["textures"]) read_textures(root["textures"]);
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
  void optional(const YAML::Node& map, std::string_view key, const std::string& path, Fn&& read) {
    const YAML::Node node = map[std::string(key)];
    if (!node.IsDefined()) return;
    const std::string field = YamlReader::join(path, std::string(key));
    locations_[field] = node;
    read(node, field);
  }

  // One value of a declared field, by the member's type.
  void read_value(const YAML::Node& n, const std::string& f, bool grey, double& out) {
    (void)grey;
    out = in_.number(n, f);
  }
  void read_value(const YAML::Node& n, const std::string& f, bool grey, glm::dvec3& out) {
    out = grey ? in_.color(n, f) : in_.vec3(n, f);
  }
  void read_value(const YAML::Node& n, const std::string& f, bool, bool& out) {
    out = in_.boolean(n, f);
  }
  void read_value(const YAML::Node& n, const std::string& f, bool, std::uint32_t& out) {
    out = in_.unsigned_int(n, f);
  }
  void read_value(const YAML::Node& n, const std::string& f, bool, std::string& out) {
    out = in_.string(n, f);
  }

  // Every declared field with a member: read when given, "required" when missing.
  template <typename Desc, typename Fields>
  void read_fields(const YAML::Node& map, const Fields& fields, Desc& desc,
                   const std::string& path) {
    for (const schema::Field<Desc>& field : fields) {
      if (!field.on_yaml()) continue;
      std::visit(
          [&](auto member) {
            if constexpr (!std::is_same_v<decltype(member), std::monostate>) {
              const std::string key(field.key(true));
              if (field.presence == schema::Presence::kRequired)
                in_.required(map, key.c_str(), path);
              optional(map, key, path, [&](const YAML::Node& n, const std::string& f) {
                read_value(n, f, field.grey_scalar, desc.*member);
              });
            }
          },
          field.member);
    }
  }

  template <typename Kind>
  void section(const YAML::Node& node, typename Kind::Desc& desc) {
    const std::string path(Kind::yaml_section);
    map_at(node, path);
    in_.check_keys(node, path, yaml_keys(Kind::fields), Kind::ignored);
    read_fields(node, Kind::fields, desc, path);
  }

  void read_materials(const YAML::Node& node) {
    if (!node.IsSequence())
      in_.fail(node, "materials", std::string("must be a list, got a ") + YamlReader::kind(node));
    static const std::vector<std::string_view> kKeys = yaml_keys(schema::MaterialKind::fields);
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "materials[" + std::to_string(i) + "]";
      const YAML::Node m = map_at(node[i], path);
      in_.check_keys(m, path, kKeys, schema::MaterialKind::ignored);
      MaterialDesc mat;
      const std::string type_field = path + ".type";
      const std::string type = in_.string(in_.required(m, "type", path), type_field);
      const auto parsed = material_type_from_string(type);
      if (!parsed)
        in_.fail(m["type"], type_field,
                 "unknown material type '" + type + "'" +
                     schema::did_you_mean(type, material_type_names()) + " (expected " +
                     joined(material_type_names()) + ")");
      mat.type = *parsed;
      apply_type_defaults(mat);
      read_fields(m, schema::MaterialKind::fields, mat, path);
      mat.pattern = read_pattern(m, path);
      // Names are checked here as well as in validate_scene, so geometry can refer to them.
      if (!material_index_.emplace(mat.name, scene_.materials.size()).second)
        in_.fail(m["name"], path + ".name", "duplicate material name '" + mat.name + "'");
      scene_.materials.push_back(std::move(mat));
    }
  }

  void read_lights(const YAML::Node& node) {
    if (!node.IsSequence())
      in_.fail(node, "lights", std::string("must be a list, got a ") + YamlReader::kind(node));
    static const std::vector<std::string_view> kKeys = yaml_keys(schema::LightKind::fields);
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "lights[" + std::to_string(i) + "]";
      const YAML::Node l = map_at(node[i], path);
      in_.check_keys(l, path, kKeys, schema::LightKind::ignored);
      LightDesc light;
      read_fields(l, schema::LightKind::fields, light, path);
      scene_.lights.push_back(std::move(light));
    }
  }

  void read_textures(const YAML::Node& node) {
    if (!node.IsSequence())
      in_.fail(node, "textures", std::string("must be a list, got a ") + YamlReader::kind(node));
    static const std::vector<std::string_view> kKeys = yaml_keys(schema::TextureKind::fields);
    std::size_t pixels_left = options_.limits.max_texture_pixels;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "textures[" + std::to_string(i) + "]";
      const YAML::Node t = map_at(node[i], path);
      in_.check_keys(t, path, kKeys, schema::TextureKind::ignored);
      TextureDesc texture;
      read_fields(t, schema::TextureKind::fields, texture, path);
      if (texture.type == "image") load_texture_image(t, path, texture, pixels_left);
      scene_.textures.push_back(std::move(texture));
    }
  }

  // Reads an image texture's file into linear RGB floats; `pixels_left` is what the scene's
  // texture budget still allows, so a scene cannot read more than the budget in total.
  void load_texture_image(const YAML::Node& section_node, const std::string& path,
                          TextureDesc& texture, std::size_t& pixels_left) {
    const std::string field = path + ".file";
    const YAML::Node node = section_node["file"];
    if (!node.IsDefined() || texture.file.empty())
      in_.fail(section_node, field, "is required for an image texture");
    const std::filesystem::path file = scene_file(node, field, texture.file);
    try {
      RgbImage image = read_rgb_image(file, pixels_left);
      pixels_left -= std::size_t{image.width} * image.height;
      if (texture.color_space == "srgb" || (texture.color_space == "auto" && image.integer_format))
        decode_srgb(image.rgb);
      texture.image_width = image.width;
      texture.image_height = image.height;
      texture.image_pixels = std::move(image.rgb);
    } catch (const std::runtime_error& e) {
      in_.fail(node, field,
               "cannot load image '" + file.lexically_normal().string() + "': " + e.what());
    }
  }

  std::uint32_t material_ref(const YAML::Node& g, const std::string& path) {
    const std::string field = path + ".material";
    const YAML::Node node = in_.required(g, "material", path);
    const std::string name = in_.string(node, field);
    const auto found = material_index_.find(name);
    if (found == material_index_.end()) {
      std::vector<std::string_view> names;
      if (scene_.materials.size() <= 1000)  // suggestions only where they are cheap
        for (const auto& m : scene_.materials) names.push_back(m.name);
      in_.fail(node, field, "unknown material '" + name + "'" + schema::did_you_mean(name, names));
    }
    locations_[field] = node;
    return static_cast<std::uint32_t>(found->second);
  }

  // A scale: one number (uniform) or three.
  glm::dvec3 scale_of(const YAML::Node& n, const std::string& f) {
    return n.IsScalar() ? glm::dvec3(in_.number(n, f)) : in_.vec3(n, f);
  }

  // pattern: { type: fibonacci_dots, color: [r, g, b], dot_count: n, dot_radius: a }
  std::optional<PatternDesc> read_pattern(const YAML::Node& material, const std::string& path) {
    std::optional<PatternDesc> result;
    optional(material, "pattern", path, [&](const YAML::Node& n, const std::string& f) {
      map_at(n, f);
      static const std::vector<std::string_view> kKeys = yaml_keys(schema::PatternKind::fields);
      in_.check_keys(n, f, kKeys);
      PatternDesc pattern;
      read_fields(n, schema::PatternKind::fields, pattern, f);
      result = pattern;
    });
    return result;
  }

  // transform: { translate: [x, y, z], rotate: { axis: [x, y, z], degrees: a }, scale: s }
  std::optional<TransformDesc> read_transform(const YAML::Node& g, const std::string& path) {
    std::optional<TransformDesc> result;
    optional(g, "transform", path, [&](const YAML::Node& n, const std::string& f) {
      map_at(n, f);
      static const std::vector<std::string_view> kKeys = yaml_keys(schema::TransformKind::fields);
      in_.check_keys(n, f, kKeys);
      TransformDesc t;
      read_fields(n, schema::TransformKind::fields, t, f);
      optional(n, "rotate", f, [&](const YAML::Node& r, const std::string& rf) {
        map_at(r, rf);
        static const std::vector<std::string_view> kRotateKeys =
            yaml_keys(schema::RotationKind::fields);
        in_.check_keys(r, rf, kRotateKeys);
        read_fields(r, schema::RotationKind::fields, t, rf);
      });
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

  // The keys a shape entry may have: the Geometry's own and the kind's fields.
  template <typename Kind>
  static std::span<const std::string_view> shape_keys() {
    static const std::vector<std::string_view> keys = [] {
      std::vector<std::string_view> all(std::begin(schema::GeometryCommon::fields),
                                        std::end(schema::GeometryCommon::fields));
      for (std::string_view key : yaml_keys(Kind::fields)) all.push_back(key);
      return all;
    }();
    return keys;
  }
  // The keys of a trimmed face's `surface`: the kind's fields without caps.
  template <typename Kind>
  static std::span<const std::string_view> surface_keys() {
    static const std::vector<std::string_view> keys = [] {
      std::vector<std::string_view> all{"type"};
      for (std::string_view key : yaml_keys(Kind::fields))
        if (key != "caps") all.push_back(key);
      return all;
    }();
    return keys;
  }

  // The YAML type names (and aliases) of every kind of a tuple, for messages and suggestions.
  template <typename Kinds>
  static std::span<const std::string_view> type_names() {
    static const std::vector<std::string_view> names = [] {
      std::vector<std::string_view> all;
      schema::for_each_kind<Kinds>([&](auto kind) {
        using Kind = decltype(kind);
        all.push_back(Kind::name);
        for (const auto& alias : Kind::aliases) all.push_back(alias.name);
      });
      return all;
    }();
    return names;
  }

  template <typename Kind>
  static bool answers_to(const std::string& type) {
    if (type == Kind::name) return true;
    for (const auto& alias : Kind::aliases)
      if (type == alias.name) return true;
    return false;
  }

  // An alias may make a field required (sdf_rounded_box: rounding).
  template <typename Kind>
  void alias_requirements(const YAML::Node& g, const std::string& type, const std::string& path) {
    for (const auto& alias : Kind::aliases)
      if (type == alias.name && !alias.requires_field.empty())
        in_.required(g, std::string(alias.requires_field).c_str(), path);
  }

  void read_geometry(const YAML::Node& node, const char* key) {
    if (!node.IsSequence())
      in_.fail(node, key, std::string("must be a list, got a ") + YamlReader::kind(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = "geometry[" + std::to_string(i) + "]";
      const YAML::Node g = map_at(node[i], path);
      const std::string type = in_.string(in_.required(g, "type", path), path + ".type");
      const auto index = static_cast<std::uint32_t>(i);
      bool found = false;
      schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
        using Kind = decltype(kind);
        if (found || !answers_to<Kind>(type)) return;
        found = true;
        in_.check_keys(g, path, shape_keys<Kind>());
        alias_requirements<Kind>(g, type, path);
        bool visible = true;
        optional(g, "visible", path, [&](auto& n, auto& f) { visible = in_.boolean(n, f); });
        read_shape<Kind>(g, path, index, visible);
      });
      if (!found)
        in_.fail(g["type"], path + ".type",
                 "unknown geometry type '" + type + "'" +
                     schema::did_you_mean(type, type_names<schema::ShapeKinds>()) + " (expected " +
                     joined(type_names<schema::ShapeKinds>()) + ")");
    }
  }

  template <typename Kind>
  void read_shape(const YAML::Node& g, const std::string& path, std::uint32_t index, bool visible) {
    if constexpr (schema::PlainShapeKind<Kind>) {
      typename Kind::Desc desc;
      read_fields(g, Kind::fields, desc, path);
      common(desc, g, path, index, visible);
      (scene_.*Kind::list).push_back(std::move(desc));
    } else if constexpr (std::is_same_v<Kind, schema::TriangleKind>) {
      TriangleMeshDesc mesh;
      common(mesh, g, path, index, visible);
      mesh.positions = {in_.vec3(in_.required(g, "v0", path), path + ".v0"),
                        in_.vec3(in_.required(g, "v1", path), path + ".v1"),
                        in_.vec3(in_.required(g, "v2", path), path + ".v2")};
      mesh.indices = {0, 1, 2};
      scene_.meshes.push_back(std::move(mesh));
    } else if constexpr (std::is_same_v<Kind, schema::MeshKind>) {
      read_mesh_entry(g, path, index, visible);
    } else if constexpr (std::is_same_v<Kind, schema::SplinePatchKind>) {
      SplinePatchDesc p = patch_fields(g, path);
      common(p, g, path, index, visible);
      scene_.patches.push_back(std::move(p));
    } else {
      static_assert(std::is_same_v<Kind, schema::TrimmedFaceKind>);
      TrimmedFaceDesc f;
      common(f, g, path, index, visible);
      f.surface = surface_fields(g, path);
      f.loops = loops_field(g, path);
      scene_.trimmed_faces.push_back(std::move(f));
    }
  }

  void read_mesh_entry(const YAML::Node& g, const std::string& path, std::uint32_t index,
                       bool visible) {
    const std::uint32_t material = material_ref(g, path);
    const YAML::Node file_node = in_.required(g, "file", path);
    const std::string file = in_.string(file_node, path + ".file");
    // RayON's placement (scale, then move) becomes the entry's transform (composed under an
    // explicit one), so that entries placing one file keep identical vertices and the
    // renderer can share them (prepared_scene.cpp).
    TransformDesc placement;
    optional(g, "position", path, [&](auto& n, auto& f) { placement.translate = in_.vec3(n, f); });
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
    const std::string type = in_.string(in_.required(s, "type", path), path + ".type");
    std::optional<TrimmedSurfaceDesc> surface;
    schema::for_each_kind<schema::SurfaceKinds>([&](auto kind) {
      using Kind = decltype(kind);
      if (surface || !answers_to<Kind>(type)) return;
      in_.check_keys(s, path, surface_keys<Kind>());
      if constexpr (schema::PlainShapeKind<Kind>) {
        typename Kind::Desc desc;
        read_fields(s, Kind::fields, desc, path);
        if constexpr (requires { desc.caps; }) desc.caps = false;  // a face is the side only
        surface = desc;
      } else {
        surface = patch_fields(s, path);
      }
    });
    if (!surface)
      in_.fail(s["type"], path + ".type",
               "unknown surface type '" + type + "' for a trimmed face" +
                   schema::did_you_mean(type, type_names<schema::SurfaceKinds>()) + " (expected " +
                   joined(type_names<schema::SurfaceKinds>()) + ")");
    return *surface;
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

  // A file a scene names (a mesh, an environment image): relative to the scene's directory,
  // and only inside the allowed roots when the loader has them.
  std::filesystem::path scene_file(const YAML::Node& node, const std::string& field,
                                   const std::string& file) {
    std::filesystem::path path(file);
    if (path.is_relative()) path = base_directory_ / path;
    if (!options_.allowed_roots.empty() && !path_is_within(path, options_.allowed_roots))
      in_.fail(node, field, "'" + file + "' is outside the directories this server may read");
    return path;
  }

  void load_environment_image(const YAML::Node& section_node, EnvironmentDesc& env) {
    const std::string field = "environment.file";
    const YAML::Node node = section_node["file"];
    if (!node.IsDefined() || env.file.empty())
      in_.fail(section_node, field, "is required for an image environment");
    const std::filesystem::path path = scene_file(node, field, env.file);
    try {
      RgbImage image = read_rgb_image(path, options_.limits.max_environment_pixels);
      env.image_width = image.width;
      env.image_height = image.height;
      env.image_pixels = std::move(image.rgb);
    } catch (const std::runtime_error& e) {
      in_.fail(node, field,
               "cannot load image '" + path.lexically_normal().string() + "': " + e.what());
    }
  }

  TriangleMeshDesc load_mesh(const YAML::Node& node, const std::string& field,
                             const std::string& file) {
    const std::filesystem::path path = scene_file(node, field, file);
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
    const std::string path(schema::RenderKind::yaml_section);
    map_at(node, path);
    in_.check_keys(node, path, yaml_keys(schema::RenderKind::fields));
    auto& r = scene_.render;
    read_fields(node, schema::RenderKind::fields, r, path);
    optional(node, "seed", path, [&](auto& n, auto& f) { r.seed = in_.seed(n, f); });
    optional(node, "integrator", path, [&](auto& n, auto& f) {
      const std::string name = in_.string(n, f);
      const auto kind = integrator_from_string(name);
      if (!kind)
        in_.fail(n, f,
                 "unknown integrator '" + name + "'" +
                     schema::did_you_mean(name, integrator_names()) + " (expected " +
                     joined(integrator_names()) + ")");
      r.integrator = *kind;
    });
    optional(node, "sampler", path, [&](auto& n, auto& f) {
      const std::string name = in_.string(n, f);
      const auto kind = sampler_from_string(name);
      if (!kind)
        in_.fail(n, f,
                 "unknown sampler '" + name + "'" + schema::did_you_mean(name, sampler_names()) +
                     " (expected " + joined(sampler_names()) + ")");
      r.sampler = *kind;
    });
    optional(node, "light_strategy", path, [&](auto& n, auto& f) {
      const std::string name = in_.string(n, f);
      const auto strategy = light_strategy_from_string(name);
      if (!strategy)
        in_.fail(n, f,
                 "unknown light strategy '" + name + "'" +
                     schema::did_you_mean(name, light_strategy_names()) + " (expected " +
                     joined(light_strategy_names()) + ")");
      r.light_strategy = *strategy;
    });
    optional(node, "device", path, [&](auto& n, auto& f) {
      const std::string name = in_.string(n, f);
      const auto device = render_device_from_string(name);
      if (!device)
        in_.fail(n, f,
                 "unknown device '" + name + "'" +
                     schema::did_you_mean(name, render_device_names()) + " (expected " +
                     joined(render_device_names()) + ")");
      r.device = *device;
    });
    optional(node, "aovs", path, [&](auto& n, auto& f) {
      if (!n.IsSequence())
        in_.fail(n, f, "must be a list of AOV names (" + joined(aov_names()) + ")");
      for (std::size_t i = 0; i < n.size(); ++i) {
        const std::string item = f + "[" + std::to_string(i) + "]";
        const std::string name = in_.string(n[i], item);
        const auto bit = aov_from_string(name);
        if (!bit)
          in_.fail(n[i], item,
                   "unknown AOV '" + name + "'" + schema::did_you_mean(name, aov_names()) +
                       " (expected " + joined(aov_names()) + ")");
        r.aovs |= *bit;
      }
    });
  }

  YamlReader& in_;
  std::filesystem::path base_directory_;
  const SceneLoadOptions& options_;
  SceneDescription scene_;
  std::unordered_map<std::string, std::size_t> material_index_;  // name -> index, O(1) lookups
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
  reader.set_lenient(options.lenient);
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
