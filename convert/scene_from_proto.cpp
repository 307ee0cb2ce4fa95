#include <algorithm>
#include <cctype>
#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "convert/proto_fields.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/scene/schema/kinds.hpp"

namespace tessera {
namespace {

namespace pb = google::protobuf;
using proto_fields::Reader;

std::string format_number(double value) {
  return schema::Checks::format(value);
}

std::string indexed(const std::string& name, std::size_t index) {
  return name + "[" + std::to_string(index) + "]";
}

template <typename Kind>
void read_section(const pb::Message& message, typename Kind::Desc& desc, Reader& reader) {
  proto_fields::read(message, Kind::fields, desc, std::string(Kind::proto_section), reader);
}

std::optional<MaterialType> material_type_from_proto(int value) {
  const pb::EnumValueDescriptor* v = v1::MaterialType_descriptor()->FindValueByNumber(value);
  if (v == nullptr) return std::nullopt;
  for (std::size_t i = 0; i < material_type_names().size(); ++i)
    if (v->name() == proto_fields::enum_value_name("MATERIAL_TYPE_", material_type_names()[i]))
      return static_cast<MaterialType>(i);
  return std::nullopt;
}

void convert_materials(const v1::Scene& in, Reader& check, std::vector<MaterialDesc>& materials) {
  for (int i = 0; i < in.materials_size(); ++i) {
    const v1::Material& m = in.materials(i);
    const std::string base = indexed("materials", static_cast<std::size_t>(i));
    MaterialDesc mat;
    if (m.type() == v1::MATERIAL_TYPE_UNSPECIFIED) {
      check.fail(base + ".type", "must be set (got MATERIAL_TYPE_UNSPECIFIED)");
    } else if (const auto type = material_type_from_proto(m.type())) {
      mat.type = *type;
    } else {
      check.fail(base + ".type", "unknown material type " + std::to_string(m.type()));
    }
    apply_type_defaults(mat);
    proto_fields::read(m, schema::MaterialKind::fields, mat, base, check);
    if (m.has_pattern()) {
      PatternDesc pattern;
      proto_fields::read(m.pattern(), schema::PatternKind::fields, pattern, base + ".pattern",
                         check);
      mat.pattern = pattern;
    }
    materials.push_back(std::move(mat));
  }
}

void convert_mesh(const v1::TriangleMesh& in, const std::string& path, proto_fields::Reader& check,
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

std::vector<double> convert_numbers(const google::protobuf::RepeatedField<double>& in,
                                    const std::string& field, proto_fields::Reader& check) {
  std::vector<double> out(in.begin(), in.end());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i])) {
      check.number(indexed(field, i), out[i]);
      break;
    }
  return out;
}
SplinePatchDesc convert_patch(const v1::SplinePatch& in, const std::string& at,
                              proto_fields::Reader& check) {
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
std::optional<TransformDesc> convert_transform(const v1::Geometry& g, const std::string& path,
                                               Reader& check) {
  if (!g.has_transform()) return std::nullopt;
  const std::string base = path + ".transform";
  TransformDesc t;
  proto_fields::read(g.transform(), schema::TransformKind::fields, t, base, check);
  if (g.transform().has_rotate())
    proto_fields::read(g.transform().rotate(), schema::RotationKind::fields, t, base + ".rotate",
                       check);
  return t;
}

// The shape's description from its message: declared fields generically, structured ones
// (triangle corners, mesh arrays, patch grids, trimming loops) here.
template <typename Kind>
typename Kind::Desc convert_shape(const pb::Message& in, const std::string& at, Reader& check) {
  if constexpr (schema::PlainShapeKind<Kind>) {
    typename Kind::Desc desc;
    proto_fields::read(in, Kind::fields, desc, at, check);
    return desc;
  } else if constexpr (std::is_same_v<Kind, schema::TriangleKind>) {
    const auto& t = static_cast<const v1::Triangle&>(in);
    TriangleMeshDesc mesh;
    mesh.positions = {check.vec3(at + ".v0", t.v0()), check.vec3(at + ".v1", t.v1()),
                      check.vec3(at + ".v2", t.v2())};
    mesh.indices = {0, 1, 2};
    return mesh;
  } else if constexpr (std::is_same_v<Kind, schema::MeshKind>) {
    TriangleMeshDesc mesh;
    convert_mesh(static_cast<const v1::TriangleMesh&>(in), at, check, mesh);
    return mesh;
  } else if constexpr (std::is_same_v<Kind, schema::SplinePatchKind>) {
    return convert_patch(static_cast<const v1::SplinePatch&>(in), at + ".", check);
  } else {
    static_assert(std::is_same_v<Kind, schema::TrimmedFaceKind>);
    const auto& face = static_cast<const v1::TrimmedFace&>(in);
    TrimmedFaceDesc f;
    const pb::FieldDescriptor* surface =
        face.GetReflection()->GetOneofFieldDescriptor(face, face.GetDescriptor()->oneof_decl(0));
    bool found = false;
    if (surface != nullptr)
      schema::for_each_kind<schema::SurfaceKinds>([&](auto kind) {
        using Surface = decltype(kind);
        if (found || surface->name() != schema::surface_proto_name<Surface>()) return;
        found = true;
        auto desc = convert_shape<Surface>(face.GetReflection()->GetMessage(face, surface),
                                           at + "." + surface->name(), check);
        if constexpr (requires { desc.caps; }) desc.caps = false;  // a face is the side only
        f.surface.template emplace<typename Surface::Desc>(std::move(desc));
      });
    if (!found)
      check.fail(at + ".surface",
                 "is required: set one of plane, disk, rectangle, sphere, cylinder, cone, torus "
                 "or patch");
    for (int k = 0; k < face.loops_size(); ++k) {
      const std::string field = indexed(at + ".loops", static_cast<std::size_t>(k));
      const std::vector<double> uv = convert_numbers(face.loops(k).uv(), field + ".uv", check);
      if (uv.size() % 2 != 0)
        check.fail(field + ".uv", "must hold u, v of each point (an even number of values), got " +
                                      std::to_string(uv.size()));
      std::vector<glm::dvec2>& loop = f.loops.emplace_back();
      for (std::size_t i = 0; i + 1 < uv.size(); i += 2) loop.emplace_back(uv[i], uv[i + 1]);
    }
    return f;
  }
}

std::string shape_names() {
  std::string names;
  schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
    if (!names.empty()) names += ", ";
    names += decltype(kind)::proto_name;
  });
  return names;
}

void convert_geometry(const v1::Scene& in, Reader& check, SceneDescription& scene) {
  std::unordered_map<std::string_view, std::uint32_t> material_index;
  material_index.reserve(scene.materials.size());
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    material_index.emplace(scene.materials[i].name, static_cast<std::uint32_t>(i));
  const pb::OneofDescriptor* shape_oneof = v1::Geometry::descriptor()->FindOneofByName("shape");

  for (int i = 0; i < in.geometry_size(); ++i) {
    const v1::Geometry& g = in.geometry(i);
    const auto index = static_cast<std::uint32_t>(i);
    const std::string path = indexed("geometry", index);

    std::uint32_t material = 0;
    if (g.material().empty()) {
      check.fail(path + ".material", "is required but missing");
    } else if (const auto found = material_index.find(g.material());
               found != material_index.end()) {
      material = found->second;
    } else {
      check.fail(path + ".material", "unknown material '" + g.material() + "'");
    }
    const bool visible = !g.has_visible() || g.visible();
    const std::optional<TransformDesc> transform = convert_transform(g, path, check);

    const pb::FieldDescriptor* shape = g.GetReflection()->GetOneofFieldDescriptor(g, shape_oneof);
    if (shape == nullptr) {
      check.fail(path + ".shape", "is required: set one of " + shape_names());
      continue;
    }
    schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
      using Kind = decltype(kind);
      if (shape->name() != Kind::proto_name) return;
      auto desc = convert_shape<Kind>(g.GetReflection()->GetMessage(g, shape),
                                      path + "." + shape->name(), check);
      desc.material = material;
      desc.visible = visible;
      desc.source_index = index;
      desc.transform = transform;
      if constexpr (std::is_same_v<Kind, schema::TriangleKind>)
        scene.meshes.push_back(std::move(desc));
      else
        (scene.*Kind::list).push_back(std::move(desc));
    });
  }
}

// Structure first, then validate_scene: an issue validation repeats for a field structure
// already reported (a non-finite vector, a bad material reference) is dropped.
bool already_reported(const std::vector<SceneIssue>& structural, const SceneIssue& issue) {
  for (const SceneIssue& earlier : structural) {
    const std::string& a = earlier.field;
    const std::string& b = issue.field;
    const std::string& shorter = a.size() < b.size() ? a : b;
    const std::string& longer = a.size() < b.size() ? b : a;
    if (longer.compare(0, shorter.size(), shorter) == 0 &&
        (longer.size() == shorter.size() || longer[shorter.size()] == '.' ||
         longer[shorter.size()] == '['))
      return true;
  }
  return false;
}

// "PREFIX_A, PREFIX_B or PREFIX_C": the accepted values in the request's own terms.
std::string proto_enum_values(std::string_view prefix, std::span<const std::string_view> names) {
  std::vector<std::string> values;
  for (std::string_view name : names) values.push_back(proto_fields::enum_value_name(prefix, name));
  const std::vector<std::string_view> views(values.begin(), values.end());
  return joined(views);
}

}  // namespace

RenderSettings settings_from_proto(const v1::RenderSettings& in) {
  RenderSettings out;
  // Every render field is an integer: nothing can be non-finite, so no issue is raised here
  // (range checks are validate_scene's).
  std::vector<SceneIssue> ignored;
  Reader reader(ignored);
  proto_fields::read(in, schema::RenderKind::fields, out, "settings", reader);
  out.seed = in.seed();
  const pb::EnumValueDescriptor* integrator =
      v1::Integrator_descriptor()->FindValueByNumber(in.integrator());
  for (std::size_t i = 0; integrator != nullptr && i < integrator_names().size(); ++i)
    if (integrator->name() == proto_fields::enum_value_name("INTEGRATOR_", integrator_names()[i]))
      out.integrator = static_cast<IntegratorKind>(i);
  // UNSPECIFIED (and an unknown value, which scene_from_proto reports) keeps the default.
  const pb::EnumValueDescriptor* sampler =
      v1::Sampler_descriptor()->FindValueByNumber(in.sampler());
  for (std::size_t i = 0; sampler != nullptr && i < sampler_names().size(); ++i)
    if (sampler->name() == proto_fields::enum_value_name("SAMPLER_", sampler_names()[i]))
      out.sampler = static_cast<SamplerKind>(i);
  const pb::EnumValueDescriptor* strategy =
      v1::LightStrategy_descriptor()->FindValueByNumber(in.light_strategy());
  for (std::size_t i = 0; strategy != nullptr && i < light_strategy_names().size(); ++i)
    if (strategy->name() ==
        proto_fields::enum_value_name("LIGHT_STRATEGY_", light_strategy_names()[i]))
      out.light_strategy = static_cast<LightStrategy>(i);
  const pb::EnumValueDescriptor* device =
      v1::RenderDevice_descriptor()->FindValueByNumber(in.device());
  for (std::size_t i = 0; device != nullptr && i < render_device_names().size(); ++i)
    if (device->name() == proto_fields::enum_value_name("RENDER_DEVICE_", render_device_names()[i]))
      out.device = static_cast<RenderDevice>(i);
  out.aovs = aov_mask_from_proto(in);
  return out;
}

v1::RenderSettings settings_to_proto(const RenderSettings& in) {
  v1::RenderSettings out;
  proto_fields::write(in, schema::RenderKind::fields, out);
  out.set_seed(in.seed);
  const auto* integrator = v1::Integrator_descriptor()->FindValueByName(
      proto_fields::enum_value_name("INTEGRATOR_", to_string(in.integrator)));
  out.set_integrator(static_cast<v1::Integrator>(integrator->number()));
  const auto* sampler = v1::Sampler_descriptor()->FindValueByName(
      proto_fields::enum_value_name("SAMPLER_", to_string(in.sampler)));
  out.set_sampler(static_cast<v1::Sampler>(sampler->number()));
  const auto* strategy = v1::LightStrategy_descriptor()->FindValueByName(
      proto_fields::enum_value_name("LIGHT_STRATEGY_", to_string(in.light_strategy)));
  out.set_light_strategy(static_cast<v1::LightStrategy>(strategy->number()));
  const auto* device = v1::RenderDevice_descriptor()->FindValueByName(
      proto_fields::enum_value_name("RENDER_DEVICE_", to_string(in.device)));
  out.set_device(static_cast<v1::RenderDevice>(device->number()));
  for (std::size_t i = 0; i < aov_names().size(); ++i)
    if ((in.aovs & (1u << i)) != 0)
      out.add_aovs(static_cast<v1::Aov>(
          v1::Aov_descriptor()
              ->FindValueByName(proto_fields::enum_value_name("AOV_", aov_names()[i]))
              ->number()));
  return out;
}

std::uint32_t aov_mask_from_proto(const v1::RenderSettings& settings) {
  std::uint32_t mask = 0;
  for (int aov : settings.aovs()) {
    const pb::EnumValueDescriptor* value = v1::Aov_descriptor()->FindValueByNumber(aov);
    for (std::size_t i = 0; value != nullptr && i < aov_names().size(); ++i)
      if (value->name() == proto_fields::enum_value_name("AOV_", aov_names()[i])) mask |= 1u << i;
  }
  return mask;
}

SceneConversion scene_from_proto(const v1::Scene& in, const v1::RenderSettings& settings,
                                 const SceneLimits& limits) {
  SceneConversion result;
  Reader check(result.issues);
  SceneDescription scene;
  if (in.has_camera()) read_section<schema::CameraKind>(in.camera(), scene.camera, check);
  if (in.has_background())
    read_section<schema::BackgroundKind>(in.background(), scene.background, check);
  if (in.has_environment()) {
    EnvironmentDesc& env = scene.environment.emplace();
    read_section<schema::EnvironmentKind>(in.environment(), env, check);
    env.image_pixels.assign(in.environment().image_pixels().begin(),
                            in.environment().image_pixels().end());
  }
  for (int i = 0; i < in.textures_size(); ++i) {
    const v1::Texture& t = in.textures(i);
    TextureDesc& texture = scene.textures.emplace_back();
    proto_fields::read(t, schema::TextureKind::fields, texture,
                       indexed("textures", static_cast<std::size_t>(i)), check);
    texture.image_pixels.assign(t.image_pixels().begin(), t.image_pixels().end());
  }
  for (int i = 0; i < in.lights_size(); ++i) {
    LightDesc& light = scene.lights.emplace_back();
    proto_fields::read(in.lights(i), schema::LightKind::fields, light,
                       indexed("lights", static_cast<std::size_t>(i)), check);
  }
  convert_materials(in, check, scene.materials);
  convert_geometry(in, check, scene);
  scene.render = settings_from_proto(settings);
  if (!v1::Integrator_IsValid(settings.integrator()))
    check.fail("settings.integrator",
               "unknown integrator value " + std::to_string(settings.integrator()));
  if (!v1::Sampler_IsValid(settings.sampler()))
    check.fail("settings.sampler", "unknown sampler value " + std::to_string(settings.sampler()) +
                                       " (expected " +
                                       proto_enum_values("SAMPLER_", sampler_names()) + ")");
  if (!v1::LightStrategy_IsValid(settings.light_strategy()))
    check.fail("settings.light_strategy",
               "unknown light strategy value " + std::to_string(settings.light_strategy()) +
                   " (expected " + proto_enum_values("LIGHT_STRATEGY_", light_strategy_names()) +
                   ")");
  if (!v1::RenderDevice_IsValid(settings.device()))
    check.fail("settings.device",
               "unknown device value " + std::to_string(settings.device()) + " (expected " +
                   proto_enum_values("RENDER_DEVICE_", render_device_names()) + ")");
  for (int i = 0; i < settings.aovs_size(); ++i)
    if (settings.aovs(i) < v1::AOV_ALBEDO || !v1::Aov_IsValid(settings.aovs(i)))
      check.fail("settings.aovs[" + std::to_string(i) + "]",
                 "unknown AOV value " + std::to_string(settings.aovs(i)));

  const std::vector<SceneIssue> structural = result.issues;
  for (SceneIssue& issue : validate_scene(scene, limits, schema::PathStyle::kProto))
    if (!already_reported(structural, issue)) result.issues.push_back(std::move(issue));
  if (result.issues.empty())
    result.scene = std::move(scene);
  else
    schema::sort_in_input_order(result.issues, schema::PathStyle::kProto);
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

}  // namespace tessera
