// validate_scene: the semantic checks every input path shares, driven by the kind
// declarations (scene/schema/kinds.hpp) and written in the caller's path style.
#include <algorithm>
#include <string>
#include <unordered_map>

#include "schema/field_rules.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/schema/kinds.hpp"
#include "tessera/scene/schema/suggest.hpp"
#include "tessera/scene/spline_geometry.hpp"

namespace tessera {
namespace {

using schema::Checks;
using schema::PathStyle;

std::string geometry_path(std::uint32_t source_index) {
  return "geometry[" + std::to_string(source_index) + "]";
}

// Where a shape's own fields live: `geometry[3]` in YAML, `geometry[3].sphere` in protobuf.
template <typename Kind>
std::string shape_prefix(std::uint32_t source_index, PathStyle style) {
  std::string path = geometry_path(source_index);
  if (style == PathStyle::kProto) path += "." + std::string(Kind::proto_name);
  return path;
}

template <typename Kind>
std::string section_prefix(PathStyle style) {
  return std::string(style == PathStyle::kYaml ? Kind::yaml_section : Kind::proto_section);
}

class SceneValidator {
 public:
  SceneValidator(const SceneDescription& scene, const SceneLimits& limits, PathStyle style,
                 std::vector<SceneIssue>& issues)
      : scene_(scene), limits_(limits), style_(style), issues_(issues) {}

  void run() {
    section<schema::CameraKind>(scene_.camera);
    section<schema::BackgroundKind>(scene_.background);
    if (scene_.environment) {
      section<schema::EnvironmentKind>(*scene_.environment);
      const std::size_t pixels =
          std::size_t{scene_.environment->image_width} * scene_.environment->image_height;
      if (pixels > limits_.max_environment_pixels)
        at("environment")
            .fail(style_ == PathStyle::kYaml ? "file" : "image_width",
                  "the image has " + std::to_string(pixels) + " pixels, more than the " +
                      std::to_string(limits_.max_environment_pixels) + " allowed");
    }
    if (scene_.lights.size() > limits_.max_shapes_per_type)
      at("").fail("lights", "at most " + std::to_string(limits_.max_shapes_per_type) +
                                " lights, got " + std::to_string(scene_.lights.size()));
    for (std::size_t i = 0; i < scene_.lights.size(); ++i) {
      Checks check = at("lights[" + std::to_string(i) + "]");
      if (schema::check_fields(scene_.lights[i], schema::LightKind::fields, check))
        schema::LightKind::check(scene_.lights[i], check);
    }
    textures();
    materials();
    schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
      using Kind = decltype(kind);
      if constexpr (schema::PlainShapeKind<Kind>)
        for (const auto& shape : scene_.*Kind::list) plain_shape<Kind>(shape);
    });
    for (const auto& patch : scene_.patches) {
      const std::string base = shape_prefix<schema::SplinePatchKind>(patch.source_index, style_);
      patch_shape(patch, base);
      common<schema::SplinePatchKind>(patch);
    }
    for (const auto& face : scene_.trimmed_faces) trimmed_face(face);
    meshes();
    totals();
    render();
  }

 private:
  Checks at(std::string prefix) { return Checks(issues_, std::move(prefix), style_); }

  template <typename Kind>
  void section(const typename Kind::Desc& desc) {
    Checks check = at(section_prefix<Kind>(style_));
    if (schema::check_fields(desc, Kind::fields, check)) Kind::check(desc, check);
  }

  void textures() {
    if (scene_.textures.size() > limits_.max_textures)
      at("").fail("textures", "at most " + std::to_string(limits_.max_textures) +
                                  " textures, got " + std::to_string(scene_.textures.size()));
    std::size_t total_pixels = 0;
    for (std::size_t i = 0; i < scene_.textures.size(); ++i) {
      const TextureDesc& t = scene_.textures[i];
      Checks check = at("textures[" + std::to_string(i) + "]");
      if (t.name.empty())
        check.fail("name", "must not be empty");
      else if (!texture_names_.emplace(t.name, i).second)
        check.fail("name", "duplicate texture name '" + t.name + "'");
      if (schema::check_fields(t, schema::TextureKind::fields, check))
        schema::TextureKind::check(t, check);
      total_pixels += std::size_t{t.image_width} * t.image_height;
      if (total_pixels > limits_.max_texture_pixels) {
        check.fail(style_ == PathStyle::kYaml ? "file" : "image_width",
                   "the textures up to this one have " + std::to_string(total_pixels) +
                       " pixels, more than the " + std::to_string(limits_.max_texture_pixels) +
                       " allowed in one scene");
        break;
      }
    }
  }

  void texture_reference(Checks& check, const char* field, const std::string& name) {
    if (name.empty() || texture_names_.contains(name)) return;
    std::vector<std::string_view> names;
    for (const TextureDesc& t : scene_.textures) names.push_back(t.name);
    check.fail(field, "unknown texture '" + name + "'" + schema::did_you_mean(name, names));
  }

  void materials() {
    std::unordered_map<std::string_view, std::size_t> first_of_name;
    first_of_name.reserve(scene_.materials.size());
    for (std::size_t i = 0; i < scene_.materials.size(); ++i) {
      const MaterialDesc& m = scene_.materials[i];
      Checks check = at("materials[" + std::to_string(i) + "]");
      if (m.name.empty())
        check.fail("name", "must not be empty");
      else if (!first_of_name.emplace(m.name, i).second)
        check.fail("name", "duplicate material name '" + m.name + "'");
      if (schema::check_fields(m, schema::MaterialKind::fields, check))
        schema::MaterialKind::check(m, check);
      texture_reference(check, "albedo_texture", m.albedo_texture);
      texture_reference(check, "roughness_texture", m.roughness_texture);
      if (m.pattern) {
        Checks pattern = check.nested("pattern");
        if (schema::check_fields(*m.pattern, schema::PatternKind::fields, pattern))
          schema::PatternKind::check(*m.pattern, pattern);
      }
    }
  }

  bool emits(std::uint32_t material) const {
    if (material >= scene_.materials.size()) return false;
    const glm::dvec3 e = scene_.materials[material].emitted_radiance();
    return e.x > 0.0 || e.y > 0.0 || e.z > 0.0;
  }

  // The Geometry entry's own fields: material, visible, transform (same paths in both styles).
  template <typename Kind, typename Desc>
  void common(const Desc& shape) {
    Checks check = at(geometry_path(shape.source_index));
    if (shape.material >= scene_.materials.size())
      check.fail("material", "refers to material index " + std::to_string(shape.material) +
                                 " but the scene has " + std::to_string(scene_.materials.size()));
    if (shape.transform) {
      Checks transform = check.nested("transform");
      schema::check_fields(*shape.transform, schema::TransformKind::fields, transform);
      Checks rotate = transform.nested("rotate");
      schema::check_fields(*shape.transform, schema::RotationKind::fields, rotate);
    }
    if constexpr (requires { Kind::may_emit; }) {
      if (!Kind::may_emit && emits(shape.material))
        check.fail("material",
                   "an infinite plane cannot emit light (its power would be infinite); use the "
                   "background or a large rectangle or disk");
    }
  }

  template <typename Kind>
  void plain_shape(const typename Kind::Desc& shape) {
    Checks check = at(shape_prefix<Kind>(shape.source_index, style_));
    if (schema::check_fields(shape, Kind::fields, check)) Kind::check(shape, check);
    common<Kind>(shape);
  }

  void add_builder_issue(const std::string& error) {
    const std::size_t colon = error.find(": ");
    if (colon == std::string::npos)
      issues_.push_back(SceneIssue{"", 0, "", error});
    else
      issues_.push_back(SceneIssue{"", 0, error.substr(0, colon), error.substr(colon + 2)});
  }

  // Patches are checked by building them (the builder names the field and the reason);
  // sizes are bounded first so no input allocates without limit.
  void patch_shape(const SplinePatchDesc& p, const std::string& base) {
    Checks check = at(base);
    if (p.count_u < 4 || p.count_v < 4) {
      check.fail(p.count_u < 4 ? "count_u" : "count_v",
                 "must be at least 4 (bicubic), got " +
                     std::to_string(p.count_u < 4 ? p.count_u : p.count_v));
      return;
    }
    const std::size_t count = std::size_t{p.count_u} * p.count_v;
    if (p.control_points.size() != count) {
      check.fail("control_points", "must have count_u * count_v = " + std::to_string(count) +
                                       " points, got " + std::to_string(p.control_points.size()));
      return;
    }
    // Counted from the points actually given, so the limit bounds what building allocates.
    control_points_ += count;
    if (control_points_ > limits_.max_patch_control_points) return;  // reported in totals()
    // The builder checks finiteness; the magnitude bound is the scene model's (schema).
    for (std::size_t i = 0; i < count; ++i)
      if (!check.finite("control_points[" + std::to_string(i) + "]", p.control_points[i])) return;
    for (std::size_t i = 0; i < p.weights.size(); ++i)
      if (!check.finite("weights[" + std::to_string(i) + "]", p.weights[i])) return;
    SplinePatchPool pool;
    SplinePatch patch;
    const std::string error =
        build_spline_patch(to_spline_patch_description(p, false), pool, patch, base);
    if (!error.empty()) add_builder_issue(error);
  }

  void trimmed_face(const TrimmedFaceDesc& f) {
    const std::string base = shape_prefix<schema::TrimmedFaceKind>(f.source_index, style_);
    std::visit(
        [&](const auto& surface) {
          using S = std::decay_t<decltype(surface)>;
          schema::for_each_kind<schema::SurfaceKinds>([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (std::is_same_v<typename Kind::Desc, S>) {
              const std::string prefix =
                  base + "." +
                  (style_ == PathStyle::kYaml ? std::string("surface")
                                              : std::string(schema::surface_proto_name<Kind>()));
              if constexpr (schema::PlainShapeKind<Kind>) {
                Checks check = at(prefix);
                if (schema::check_fields(surface, Kind::fields, check)) Kind::check(surface, check);
              } else if constexpr (std::is_same_v<S, SplinePatchDesc>) {
                patch_shape(surface, prefix);  // spelled out: clang 14 instantiates the else
              }
            }
          });
        },
        f.surface);
    std::size_t points = 0;
    for (const auto& loop : f.loops) points += loop.size();
    trim_points_ += points;
    if (trim_points_ <= limits_.max_trim_points) {
      TrimPool pool;
      TrimRegion region;
      const std::string error =
          build_trim_region(f.loops, trimmed_surface_periodicity(f.surface), pool, region, base);
      if (!error.empty()) add_builder_issue(error);
    }
    common<schema::TrimmedFaceKind>(f);
  }

  static bool single_inline_triangle(const TriangleMeshDesc& mesh) {
    return mesh.source_file.empty() && mesh.positions.size() == 3 && mesh.indices.size() == 3 &&
           mesh.indices[0] == 0 && mesh.indices[1] == 1 && mesh.indices[2] == 2;
  }

  void meshes() {
    for (const auto& mesh : scene_.meshes) {
      const bool triangle = single_inline_triangle(mesh);
      std::string prefix = geometry_path(mesh.source_index);
      if (style_ == PathStyle::kProto) prefix += triangle ? ".triangle" : ".mesh";
      Checks check = at(prefix);
      const std::string where = mesh.source_file.empty() ? "" : " (" + mesh.source_file + ")";
      if (mesh.indices.size() % 3 != 0)
        check.fail("indices", "count must be a multiple of 3" + where);
      for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        std::string field = triangle ? "v" : "positions[";
        field += std::to_string(i);
        if (!triangle) field.append("]").append(where);
        if (!check.finite(field, mesh.positions[i])) break;
      }
      for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.positions.size()) {
          check.fail("indices[" + std::to_string(i) + "]",
                     "vertex index " + std::to_string(mesh.indices[i]) + " out of range (" +
                         std::to_string(mesh.positions.size()) + " vertices)" + where);
          break;
        }
      const auto per_vertex = [&](const char* name, std::size_t size) {
        if (size != 0 && size != mesh.positions.size())
          check.fail(name, "must be empty or one per vertex (" +
                               std::to_string(mesh.positions.size()) + "), got " +
                               std::to_string(size) + where);
      };
      per_vertex("normals", mesh.normals.size());
      per_vertex("uvs", mesh.uvs.size());
      if (triangle)
        common<schema::TriangleKind>(mesh);
      else
        common<schema::MeshKind>(mesh);
      triangles_ += mesh.indices.size() / 3;
    }
  }

  void totals() {
    Checks check = at("geometry");
    const auto over = [&](std::size_t count, std::size_t limit, const char* what) {
      if (count > limit)
        check.fail("", "scene has " + std::to_string(count) + " " + what +
                           ", more than the limit of " + std::to_string(limit));
    };
    over(control_points_, limits_.max_patch_control_points, "patch control points");
    over(trim_points_, limits_.max_trim_points, "trimming loop points");
    over(triangles_, limits_.max_triangles, "triangles");
    over(triangles_ + scene_.analytic_shape_count(), limits_.max_primitives,
         "primitives (triangles and other shapes)");
    // The renderer names triangles (baked, or each placement's of shared geometry) with the
    // 27 index bits of a primitive reference, whatever limit a server configures.
    constexpr std::size_t kNamedTriangles = std::size_t{1} << 27;
    if (triangles_ > kNamedTriangles)
      check.fail("", "scene has " + std::to_string(triangles_) +
                         " triangles, more than the renderer can name (2^27)");
    std::size_t largest = 0;
    schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
      using Kind = decltype(kind);
      if constexpr (requires { Kind::list; })
        if constexpr (!std::is_same_v<typename Kind::Desc, TriangleMeshDesc>)
          largest = std::max(largest, (scene_.*Kind::list).size());
    });
    over(largest, limits_.max_shapes_per_type, "shapes of one type");
  }

  void render() {
    const RenderSettings& r = scene_.render;
    Checks check = at(section_prefix<schema::RenderKind>(style_));
    const auto in_u32 = [&](const schema::Field<RenderSettings>& field, std::uint32_t lo,
                            std::uint32_t hi) {
      const std::uint32_t value = r.*std::get<std::uint32_t RenderSettings::*>(field.member);
      if (value < lo || value > hi)
        check.fail(field.key(check.yaml()), "must be in [" + std::to_string(lo) + ", " +
                                                std::to_string(hi) + "], got " +
                                                std::to_string(value));
    };
    const auto& fields = schema::RenderKind::fields;
    in_u32(fields[0], 1, limits_.max_width);
    in_u32(fields[1], 1, limits_.max_height);
    const std::size_t pixels = std::size_t{r.width} * r.height;
    if (pixels > limits_.max_pixels)
      check.fail(fields[0].key(check.yaml()), "width x height is " + std::to_string(pixels) +
                                                  " pixels, more than the limit of " +
                                                  std::to_string(limits_.max_pixels));
    in_u32(fields[2], 1, limits_.max_samples_per_pixel);
    in_u32(fields[3], 1, limits_.max_depth);
    in_u32(fields[4], limits_.min_tile_size, limits_.max_tile_size);
    // The declared rules of the other fields (clamp, pixel filter, target error): the sizes
    // above take their bounds from the limits instead.
    schema::check_fields(r, fields, check);
    if (r.adaptive() && r.min_samples_per_pixel > r.samples_per_pixel) {
      const auto min_spp = std::find_if(std::begin(fields), std::end(fields), [](const auto& f) {
        return f.name == std::string_view("min_samples_per_pixel");
      });
      check.fail(min_spp->key(check.yaml()), "must not exceed samples_per_pixel (" +
                                                 std::to_string(r.samples_per_pixel) + "), got " +
                                                 std::to_string(r.min_samples_per_pixel));
    }
    passes(r, check);
    if ((r.aovs & ~kAllAovs) != 0) check.fail("aovs", "unknown AOV bits set");
    if (r.aovs != 0 && r.integrator != IntegratorKind::kPath)
      check.fail("aovs", std::string("AOVs come with the path integrator, not '") +
                             to_string(r.integrator) + "'");
  }

  // Passes split samples_per_pixel into contiguous sample ranges, so there can be no more
  // of them than samples, and adaptive sampling (which stops pixels on statistics a pass
  // boundary would cut) renders in one.
  static void passes(const RenderSettings& r, Checks& check) {
    if (r.pass_count() <= 1) return;
    if (r.passes > r.samples_per_pixel)
      check.fail("passes", "must not exceed samples_per_pixel (" +
                               std::to_string(r.samples_per_pixel) + "), got " +
                               std::to_string(r.passes));
    if (r.adaptive())
      check.fail("passes", "must be 0 or 1 with adaptive sampling (target_error " +
                               Checks::format(r.target_error) + "), got " +
                               std::to_string(r.passes));
  }

  const SceneDescription& scene_;
  const SceneLimits& limits_;
  PathStyle style_;
  std::vector<SceneIssue>& issues_;
  std::unordered_map<std::string_view, std::size_t> texture_names_;
  std::size_t control_points_ = 0;
  std::size_t trim_points_ = 0;
  std::size_t triangles_ = 0;
};

}  // namespace

std::vector<SceneIssue> validate_scene(const SceneDescription& scene, const SceneLimits& limits,
                                       schema::PathStyle style) {
  std::vector<SceneIssue> issues;
  SceneValidator(scene, limits, style, issues).run();
  schema::sort_in_input_order(issues, style);
  return issues;
}

}  // namespace tessera
