#include <algorithm>
#include <optional>
#include <type_traits>
#include <variant>
#include <vector>

#include "convert/proto_fields.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/scene/schema/kinds.hpp"

namespace tessera {

namespace {

namespace pb = google::protobuf;

bool is_single_inline_triangle(const TriangleMeshDesc& mesh) {
  return mesh.source_file.empty() && mesh.positions.size() == 3 && mesh.indices.size() == 3 &&
         mesh.indices[0] == 0 && mesh.indices[1] == 1 && mesh.indices[2] == 2;
}

template <typename Repeated>
void add_points(Repeated* out, const std::vector<glm::dvec3>& points) {
  out->Reserve(static_cast<int>(points.size() * 3));
  for (const glm::dvec3& p : points) {
    out->Add(p.x);
    out->Add(p.y);
    out->Add(p.z);
  }
}

void write_patch(const SplinePatchDesc& p, v1::SplinePatch* out) {
  proto_fields::write(p, schema::SplinePatchKind::fields, *out);
  add_points(out->mutable_control_points(), p.control_points);
  out->mutable_weights()->Add(p.weights.begin(), p.weights.end());
  out->mutable_knots_u()->Add(p.knots_u.begin(), p.knots_u.end());
  out->mutable_knots_v()->Add(p.knots_v.begin(), p.knots_v.end());
}

void write_mesh(const TriangleMeshDesc& mesh, v1::TriangleMesh* out) {
  add_points(out->mutable_positions(), mesh.positions);
  out->mutable_indices()->Add(mesh.indices.begin(), mesh.indices.end());
  add_points(out->mutable_normals(), mesh.normals);
  out->mutable_uvs()->Reserve(static_cast<int>(mesh.uvs.size() * 2));
  for (const glm::dvec2& uv : mesh.uvs) {
    out->add_uvs(uv.x);
    out->add_uvs(uv.y);
  }
}

// The oneof member of `parent` called `name`, set and returned for writing.
pb::Message& mutable_child(pb::Message& parent, std::string_view name) {
  return *parent.GetReflection()->MutableMessage(&parent, proto_fields::find(parent, name));
}

template <typename Kind>
void write_shape(const typename Kind::Desc& shape, pb::Message& out) {
  if constexpr (schema::PlainShapeKind<Kind>) {
    proto_fields::write(shape, Kind::fields, out);
  } else if constexpr (std::is_same_v<Kind, schema::TriangleKind>) {
    auto& t = static_cast<v1::Triangle&>(out);
    proto_fields::write_vec3(*t.mutable_v0(), shape.positions[0]);
    proto_fields::write_vec3(*t.mutable_v1(), shape.positions[1]);
    proto_fields::write_vec3(*t.mutable_v2(), shape.positions[2]);
  } else if constexpr (std::is_same_v<Kind, schema::MeshKind>) {
    write_mesh(shape, &static_cast<v1::TriangleMesh&>(out));
  } else if constexpr (std::is_same_v<Kind, schema::SplinePatchKind>) {
    write_patch(shape, &static_cast<v1::SplinePatch&>(out));
  } else {
    static_assert(std::is_same_v<Kind, schema::TrimmedFaceKind>);
    auto& face = static_cast<v1::TrimmedFace&>(out);
    std::visit(
        [&](const auto& surface) {
          using S = std::decay_t<decltype(surface)>;
          schema::for_each_kind<schema::SurfaceKinds>([&](auto kind) {
            using Surface = decltype(kind);
            if constexpr (std::is_same_v<typename Surface::Desc, S>)
              write_shape<Surface>(surface,
                                   mutable_child(face, schema::surface_proto_name<Surface>()));
          });
        },
        shape.surface);
    for (const auto& loop : shape.loops) {
      v1::UvLoop* out_loop = face.add_loops();
      for (const glm::dvec2& uv : loop) {
        out_loop->add_uv(uv.x);
        out_loop->add_uv(uv.y);
      }
    }
  }
}

void write_transform(const std::optional<TransformDesc>& transform, v1::Geometry* g) {
  if (!transform) return;
  v1::Transform* out = g->mutable_transform();
  proto_fields::write(*transform, schema::TransformKind::fields, *out);
  proto_fields::write(*transform, schema::RotationKind::fields, *out->mutable_rotate());
}

}  // namespace

v1::MaterialType material_type_to_proto(MaterialType type) {
  const pb::EnumValueDescriptor* value = v1::MaterialType_descriptor()->FindValueByName(
      proto_fields::enum_value_name("MATERIAL_TYPE_", to_string(type)));
  return value != nullptr ? static_cast<v1::MaterialType>(value->number())
                          : v1::MATERIAL_TYPE_UNSPECIFIED;
}

v1::Scene scene_to_proto(const SceneDescription& scene) {
  v1::Scene out;
  proto_fields::write(scene.camera, schema::CameraKind::fields, *out.mutable_camera());
  proto_fields::write(scene.background, schema::BackgroundKind::fields, *out.mutable_background());
  if (scene.environment) {
    v1::Environment* env = out.mutable_environment();
    proto_fields::write(*scene.environment, schema::EnvironmentKind::fields, *env);
    env->mutable_image_pixels()->Assign(scene.environment->image_pixels.begin(),
                                        scene.environment->image_pixels.end());
  }
  for (const TextureDesc& texture : scene.textures) {
    v1::Texture* t = out.add_textures();
    proto_fields::write(texture, schema::TextureKind::fields, *t);
    t->mutable_image_pixels()->Assign(texture.image_pixels.begin(), texture.image_pixels.end());
  }
  for (const LightDesc& light : scene.lights)
    proto_fields::write(light, schema::LightKind::fields, *out.add_lights());
  for (const MaterialDesc& m : scene.materials) {
    v1::Material* material = out.add_materials();
    material->set_type(material_type_to_proto(m.type));
    proto_fields::write(m, schema::MaterialKind::fields, *material);
    if (m.pattern)
      proto_fields::write(*m.pattern, schema::PatternKind::fields, *material->mutable_pattern());
  }

  // Each shape, in input order, written into the proto's single geometry list.
  struct Entry {
    std::uint32_t source_index;
    v1::Geometry geometry;
  };
  std::vector<Entry> entries;
  entries.reserve(scene.meshes.size() + scene.analytic_shape_count());
  const auto add = [&](const auto& shape, auto kind) {
    using Kind = decltype(kind);
    Entry& entry = entries.emplace_back();
    entry.source_index = shape.source_index;
    v1::Geometry& g = entry.geometry;
    if (shape.material < scene.materials.size())
      g.set_material(scene.materials[shape.material].name);
    g.set_visible(shape.visible);
    write_transform(shape.transform, &g);
    write_shape<Kind>(shape, mutable_child(g, Kind::proto_name));
  };
  schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
    using Kind = decltype(kind);
    if constexpr (std::is_same_v<Kind, schema::MeshKind>) {
      for (const auto& mesh : scene.meshes) {
        if (is_single_inline_triangle(mesh))
          add(mesh, schema::TriangleKind{});
        else
          add(mesh, kind);
      }
    } else if constexpr (!std::is_same_v<Kind, schema::TriangleKind>) {
      for (const auto& shape : scene.*Kind::list) add(shape, kind);
    }
  });
  // Stable: shapes of one kind keep their relative order even if indices repeat.
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.source_index < b.source_index; });
  for (Entry& entry : entries) *out.add_geometry() = std::move(entry.geometry);
  return out;
}

v1::SubmitJobRequest make_submit_request(const SceneDescription& scene, const std::string& name,
                                         std::int32_t priority) {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = scene_to_proto(scene);
  *request.mutable_settings() = settings_to_proto(scene.render);
  request.set_name(name);
  request.set_priority(priority);
  return request;
}

}  // namespace tessera
