#include "client/scene_to_proto.hpp"

#include <algorithm>
#include <vector>

namespace tessera {

namespace {

void set_vec3(v1::Vec3* out, const glm::dvec3& v) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

v1::Material material_to_proto(const MaterialDesc& m) {
  v1::Material out;
  out.set_name(m.name);
  out.set_type(material_type_to_proto(m.type));
  set_vec3(out.mutable_albedo(), m.albedo);
  set_vec3(out.mutable_emission(), m.emission);
  out.set_roughness(m.roughness);
  out.set_refractive_index(m.refractive_index);
  out.set_metallic(m.metallic);
  out.set_transmission(m.transmission);
  out.set_anisotropy(m.anisotropy);
  out.set_preset(m.preset);
  out.set_film_thickness(m.film_thickness);
  out.set_film_ior(m.film_ior);
  return out;
}

bool is_single_inline_triangle(const TriangleMeshDesc& mesh) {
  return mesh.source_file.empty() && mesh.positions.size() == 3 && mesh.indices.size() == 3 &&
         mesh.indices[0] == 0 && mesh.indices[1] == 1 && mesh.indices[2] == 2;
}

// Where one shape of the description goes in the proto's single geometry list.
struct GeometryRef {
  std::uint32_t source_index;
  enum class Kind { kSphere, kQuad, kMesh } kind;
  std::size_t index;  // into the description's array of that kind
};

}  // namespace

v1::MaterialType material_type_to_proto(MaterialType type) {
  switch (type) {
    case MaterialType::kLambertian:
      return v1::MATERIAL_TYPE_LAMBERTIAN;
    case MaterialType::kLight:
      return v1::MATERIAL_TYPE_LIGHT;
    case MaterialType::kMetal:
      return v1::MATERIAL_TYPE_METAL;
    case MaterialType::kRoughMirror:
      return v1::MATERIAL_TYPE_ROUGH_MIRROR;
    case MaterialType::kGlass:
      return v1::MATERIAL_TYPE_GLASS;
    case MaterialType::kAnisotropicMetal:
      return v1::MATERIAL_TYPE_ANISOTROPIC_METAL;
    case MaterialType::kClearCoat:
      return v1::MATERIAL_TYPE_CLEAR_COAT;
    case MaterialType::kThinFilm:
      return v1::MATERIAL_TYPE_THIN_FILM;
  }
  return v1::MATERIAL_TYPE_UNSPECIFIED;
}

v1::Scene scene_to_proto(const SceneDescription& scene) {
  v1::Scene out;
  v1::Camera* camera = out.mutable_camera();
  set_vec3(camera->mutable_position(), scene.camera.position);
  set_vec3(camera->mutable_look_at(), scene.camera.look_at);
  set_vec3(camera->mutable_up(), scene.camera.up);
  camera->set_fov_degrees(scene.camera.fov_degrees);

  set_vec3(out.mutable_background()->mutable_color(), scene.background.color);
  out.mutable_background()->set_intensity(scene.background.intensity);

  for (const MaterialDesc& m : scene.materials) *out.add_materials() = material_to_proto(m);

  std::vector<GeometryRef> order;
  order.reserve(scene.spheres.size() + scene.quads.size() + scene.meshes.size());
  for (std::size_t i = 0; i < scene.spheres.size(); ++i)
    order.push_back({scene.spheres[i].source_index, GeometryRef::Kind::kSphere, i});
  for (std::size_t i = 0; i < scene.quads.size(); ++i)
    order.push_back({scene.quads[i].source_index, GeometryRef::Kind::kQuad, i});
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    order.push_back({scene.meshes[i].source_index, GeometryRef::Kind::kMesh, i});
  // Stable: shapes of one kind keep their relative order even if indices repeat.
  std::stable_sort(order.begin(), order.end(), [](const GeometryRef& a, const GeometryRef& b) {
    return a.source_index < b.source_index;
  });

  const auto material_name = [&](std::uint32_t index) {
    return index < scene.materials.size() ? scene.materials[index].name : std::string();
  };
  for (const GeometryRef& ref : order) {
    v1::Geometry* g = out.add_geometry();
    switch (ref.kind) {
      case GeometryRef::Kind::kSphere: {
        const SphereDesc& s = scene.spheres[ref.index];
        g->set_material(material_name(s.material));
        g->set_visible(s.visible);
        set_vec3(g->mutable_sphere()->mutable_center(), s.center);
        g->mutable_sphere()->set_radius(s.radius);
        break;
      }
      case GeometryRef::Kind::kQuad: {
        const QuadDesc& q = scene.quads[ref.index];
        g->set_material(material_name(q.material));
        g->set_visible(q.visible);
        v1::Rectangle* rect = g->mutable_rectangle();
        set_vec3(rect->mutable_corner(), q.corner);
        set_vec3(rect->mutable_u(), q.u);
        set_vec3(rect->mutable_v(), q.v);
        break;
      }
      case GeometryRef::Kind::kMesh: {
        const TriangleMeshDesc& mesh = scene.meshes[ref.index];
        g->set_material(material_name(mesh.material));
        g->set_visible(mesh.visible);
        if (is_single_inline_triangle(mesh)) {
          v1::Triangle* tri = g->mutable_triangle();
          set_vec3(tri->mutable_v0(), mesh.positions[0]);
          set_vec3(tri->mutable_v1(), mesh.positions[1]);
          set_vec3(tri->mutable_v2(), mesh.positions[2]);
        } else {
          v1::TriangleMesh* out_mesh = g->mutable_mesh();
          out_mesh->mutable_positions()->Reserve(static_cast<int>(mesh.positions.size() * 3));
          for (const glm::dvec3& p : mesh.positions) {
            out_mesh->add_positions(p.x);
            out_mesh->add_positions(p.y);
            out_mesh->add_positions(p.z);
          }
          out_mesh->mutable_indices()->Add(mesh.indices.begin(), mesh.indices.end());
        }
        break;
      }
    }
  }
  return out;
}

v1::RenderSettings render_settings_to_proto(const RenderSettings& settings) {
  v1::RenderSettings out;
  out.set_width(settings.width);
  out.set_height(settings.height);
  out.set_samples_per_pixel(settings.samples_per_pixel);
  out.set_max_depth(settings.max_depth);
  out.set_tile_size(settings.tile_size);
  out.set_seed(settings.seed);
  // IntegratorKind and AovBit follow the proto enums' order, offset by their UNSPECIFIED.
  out.set_integrator(
      static_cast<v1::Integrator>(static_cast<int>(settings.integrator) + v1::INTEGRATOR_PATH));
  for (int i = 0; i < 4; ++i)
    if ((settings.aovs & (1u << i)) != 0) out.add_aovs(static_cast<v1::Aov>(v1::AOV_ALBEDO + i));
  return out;
}

std::uint32_t aov_mask_from_proto(const v1::RenderSettings& settings) {
  std::uint32_t mask = 0;
  for (int aov : settings.aovs())
    if (aov >= v1::AOV_ALBEDO && aov <= v1::AOV_PRIMITIVE_ID) mask |= 1u << (aov - v1::AOV_ALBEDO);
  return mask;
}

v1::SubmitJobRequest make_submit_request(const SceneDescription& scene, const std::string& name,
                                         std::int32_t priority) {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = scene_to_proto(scene);
  *request.mutable_settings() = render_settings_to_proto(scene.render);
  request.set_name(name);
  request.set_priority(priority);
  return request;
}

}  // namespace tessera
