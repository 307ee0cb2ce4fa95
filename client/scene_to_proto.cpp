#include "client/scene_to_proto.hpp"

#include <algorithm>
#include <functional>
#include <optional>
#include <type_traits>
#include <variant>
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

void write_patch(const SplinePatchDesc& p, v1::SplinePatch* out) {
  out->set_count_u(p.count_u);
  out->set_count_v(p.count_v);
  out->mutable_control_points()->Reserve(static_cast<int>(p.control_points.size() * 3));
  for (const glm::dvec3& point : p.control_points) {
    out->add_control_points(point.x);
    out->add_control_points(point.y);
    out->add_control_points(point.z);
  }
  out->mutable_weights()->Add(p.weights.begin(), p.weights.end());
  out->mutable_knots_u()->Add(p.knots_u.begin(), p.knots_u.end());
  out->mutable_knots_v()->Add(p.knots_v.begin(), p.knots_v.end());
}

void write_trimmed_face(const TrimmedFaceDesc& f, v1::TrimmedFace* out) {
  std::visit(
      [&](const auto& surface) {
        using S = std::decay_t<decltype(surface)>;
        if constexpr (std::is_same_v<S, PlaneDesc>) {
          set_vec3(out->mutable_plane()->mutable_point(), surface.point);
          set_vec3(out->mutable_plane()->mutable_normal(), surface.normal);
        } else if constexpr (std::is_same_v<S, DiskDesc>) {
          v1::Disk* d = out->mutable_disk();
          set_vec3(d->mutable_center(), surface.center);
          set_vec3(d->mutable_normal(), surface.normal);
          d->set_radius(surface.radius);
          d->set_inner_radius(surface.inner_radius);
        } else if constexpr (std::is_same_v<S, QuadDesc>) {
          v1::Rectangle* r = out->mutable_rectangle();
          set_vec3(r->mutable_corner(), surface.corner);
          set_vec3(r->mutable_u(), surface.u);
          set_vec3(r->mutable_v(), surface.v);
        } else if constexpr (std::is_same_v<S, SphereDesc>) {
          set_vec3(out->mutable_sphere()->mutable_center(), surface.center);
          out->mutable_sphere()->set_radius(surface.radius);
        } else if constexpr (std::is_same_v<S, CylinderDesc>) {
          v1::Cylinder* c = out->mutable_cylinder();
          set_vec3(c->mutable_base(), surface.base);
          set_vec3(c->mutable_axis(), surface.axis);
          c->set_radius(surface.radius);
          c->set_height(surface.height);
        } else if constexpr (std::is_same_v<S, ConeDesc>) {
          v1::Cone* c = out->mutable_cone();
          set_vec3(c->mutable_base(), surface.base);
          set_vec3(c->mutable_axis(), surface.axis);
          c->set_base_radius(surface.base_radius);
          c->set_top_radius(surface.top_radius);
          c->set_height(surface.height);
        } else if constexpr (std::is_same_v<S, TorusDesc>) {
          v1::Torus* t = out->mutable_torus();
          set_vec3(t->mutable_center(), surface.center);
          set_vec3(t->mutable_axis(), surface.axis);
          t->set_major_radius(surface.major_radius);
          t->set_minor_radius(surface.minor_radius);
        } else {
          write_patch(surface, out->mutable_patch());
        }
      },
      f.surface);
  for (const auto& loop : f.loops) {
    v1::UvLoop* out_loop = out->add_loops();
    for (const glm::dvec2& uv : loop) {
      out_loop->add_uv(uv.x);
      out_loop->add_uv(uv.y);
    }
  }
}

// One shape of the description and how to write it into the proto's single geometry
// list (which keeps input order).
struct GeometryRef {
  std::uint32_t source_index;
  std::function<void(v1::Geometry*)> write;
};

void set_transform(v1::Geometry* g, const std::optional<TransformDesc>& transform) {
  if (!transform) return;
  v1::Transform* out = g->mutable_transform();
  set_vec3(out->mutable_translate(), transform->translate);
  set_vec3(out->mutable_rotate()->mutable_axis(), transform->rotate_axis);
  out->mutable_rotate()->set_degrees(transform->rotate_degrees);
  set_vec3(out->mutable_scale(), transform->scale);
}

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

  const auto material_name = [&](std::uint32_t index) {
    return index < scene.materials.size() ? scene.materials[index].name : std::string();
  };
  std::vector<GeometryRef> order;
  order.reserve(scene.meshes.size() + scene.analytic_shape_count());
  // Adds every shape of `shapes`, writing the common fields and then `fill`'s.
  const auto collect = [&](const auto& shapes, auto fill) {
    for (const auto& shape : shapes)
      order.push_back({shape.source_index, [&shape, &material_name, fill](v1::Geometry* g) {
                         g->set_material(material_name(shape.material));
                         g->set_visible(shape.visible);
                         set_transform(g, shape.transform);
                         fill(shape, g);
                       }});
  };
  collect(scene.spheres, [](const SphereDesc& s, v1::Geometry* g) {
    set_vec3(g->mutable_sphere()->mutable_center(), s.center);
    g->mutable_sphere()->set_radius(s.radius);
  });
  collect(scene.quads, [](const QuadDesc& q, v1::Geometry* g) {
    v1::Rectangle* rect = g->mutable_rectangle();
    set_vec3(rect->mutable_corner(), q.corner);
    set_vec3(rect->mutable_u(), q.u);
    set_vec3(rect->mutable_v(), q.v);
  });
  collect(scene.meshes, [](const TriangleMeshDesc& mesh, v1::Geometry* g) {
    if (is_single_inline_triangle(mesh)) {
      v1::Triangle* tri = g->mutable_triangle();
      set_vec3(tri->mutable_v0(), mesh.positions[0]);
      set_vec3(tri->mutable_v1(), mesh.positions[1]);
      set_vec3(tri->mutable_v2(), mesh.positions[2]);
      return;
    }
    v1::TriangleMesh* out_mesh = g->mutable_mesh();
    out_mesh->mutable_positions()->Reserve(static_cast<int>(mesh.positions.size() * 3));
    for (const glm::dvec3& p : mesh.positions) {
      out_mesh->add_positions(p.x);
      out_mesh->add_positions(p.y);
      out_mesh->add_positions(p.z);
    }
    out_mesh->mutable_indices()->Add(mesh.indices.begin(), mesh.indices.end());
    out_mesh->mutable_normals()->Reserve(static_cast<int>(mesh.normals.size() * 3));
    for (const glm::dvec3& n : mesh.normals) {
      out_mesh->add_normals(n.x);
      out_mesh->add_normals(n.y);
      out_mesh->add_normals(n.z);
    }
    out_mesh->mutable_uvs()->Reserve(static_cast<int>(mesh.uvs.size() * 2));
    for (const glm::dvec2& uv : mesh.uvs) {
      out_mesh->add_uvs(uv.x);
      out_mesh->add_uvs(uv.y);
    }
  });
  collect(scene.planes, [](const PlaneDesc& p, v1::Geometry* g) {
    set_vec3(g->mutable_plane()->mutable_point(), p.point);
    set_vec3(g->mutable_plane()->mutable_normal(), p.normal);
  });
  collect(scene.disks, [](const DiskDesc& d, v1::Geometry* g) {
    v1::Disk* out_disk = g->mutable_disk();
    set_vec3(out_disk->mutable_center(), d.center);
    set_vec3(out_disk->mutable_normal(), d.normal);
    out_disk->set_radius(d.radius);
    out_disk->set_inner_radius(d.inner_radius);
  });
  collect(scene.cylinders, [](const CylinderDesc& c, v1::Geometry* g) {
    v1::Cylinder* out_cylinder = g->mutable_cylinder();
    set_vec3(out_cylinder->mutable_base(), c.base);
    set_vec3(out_cylinder->mutable_axis(), c.axis);
    out_cylinder->set_radius(c.radius);
    out_cylinder->set_height(c.height);
    out_cylinder->set_caps(c.caps);
  });
  collect(scene.cones, [](const ConeDesc& c, v1::Geometry* g) {
    v1::Cone* out_cone = g->mutable_cone();
    set_vec3(out_cone->mutable_base(), c.base);
    set_vec3(out_cone->mutable_axis(), c.axis);
    out_cone->set_base_radius(c.base_radius);
    out_cone->set_top_radius(c.top_radius);
    out_cone->set_height(c.height);
    out_cone->set_caps(c.caps);
  });
  collect(scene.tori, [](const TorusDesc& t, v1::Geometry* g) {
    v1::Torus* out_torus = g->mutable_torus();
    set_vec3(out_torus->mutable_center(), t.center);
    set_vec3(out_torus->mutable_axis(), t.axis);
    out_torus->set_major_radius(t.major_radius);
    out_torus->set_minor_radius(t.minor_radius);
  });
  collect(scene.sdf_boxes, [](const SdfBoxDesc& b, v1::Geometry* g) {
    v1::SdfBox* out_box = g->mutable_sdf_box();
    set_vec3(out_box->mutable_center(), b.center);
    set_vec3(out_box->mutable_half_extent(), b.half_extent);
    out_box->set_rounding(b.rounding);
  });
  collect(scene.sdf_tori, [](const SdfTorusDesc& t, v1::Geometry* g) {
    v1::SdfTorus* out_torus = g->mutable_sdf_torus();
    set_vec3(out_torus->mutable_center(), t.center);
    set_vec3(out_torus->mutable_axis(), t.axis);
    out_torus->set_major_radius(t.major_radius);
    out_torus->set_minor_radius(t.minor_radius);
  });
  collect(scene.sdf_capsules, [](const SdfCapsuleDesc& c, v1::Geometry* g) {
    v1::SdfCapsule* out_capsule = g->mutable_sdf_capsule();
    set_vec3(out_capsule->mutable_a(), c.a);
    set_vec3(out_capsule->mutable_b(), c.b);
    out_capsule->set_radius(c.radius);
  });
  collect(scene.patches, [](const SplinePatchDesc& p, v1::Geometry* g) {
    write_patch(p, g->mutable_spline_patch());
  });
  collect(scene.trimmed_faces, [](const TrimmedFaceDesc& f, v1::Geometry* g) {
    write_trimmed_face(f, g->mutable_trimmed_face());
  });
  // Stable: shapes of one kind keep their relative order even if indices repeat.
  std::stable_sort(order.begin(), order.end(), [](const GeometryRef& a, const GeometryRef& b) {
    return a.source_index < b.source_index;
  });
  for (const GeometryRef& ref : order) ref.write(out.add_geometry());
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
