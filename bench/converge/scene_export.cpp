#include "scene_export.hpp"

#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "tessera/image/exr.hpp"
#include "tessera/render/material_mapping.hpp"

namespace tessera::bench {
namespace {

using nlohmann::json;

json vec(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}
json vec(const glm::vec3& v) {
  return json::array({v.x, v.y, v.z});
}

const char* bsdf_name(BsdfKind kind) {
  switch (kind) {
    case BsdfKind::kDiffuse:
      return "diffuse";
    case BsdfKind::kConductor:
      return "conductor";
    case BsdfKind::kDielectric:
      return "dielectric";
    case BsdfKind::kThinDielectric:
      return "thin_dielectric";
    case BsdfKind::kCoated:
      return "coated";
    case BsdfKind::kEmitter:
      return "emitter";
    case BsdfKind::kConstant:
      return "constant";
    case BsdfKind::kShowNormals:
      return "show_normals";
  }
  return "unknown";
}

json material_json(const MaterialDesc& m) {
  // The renderer's reading of the material, so the peer copies what Tessera draws (a
  // preset's colour, a thin film's ior) instead of re-deriving it from the raw fields.
  const Material mapped = make_material(m);
  return {{"name", m.name},
          {"type", to_string(m.type)},
          {"bsdf", bsdf_name(mapped.kind)},
          {"albedo", vec(mapped.albedo)},
          {"emission", vec(mapped.emission)},
          {"roughness", mapped.roughness},
          {"alpha_x", mapped.alpha_x},  // GGX roughness of conductors and glass
          {"alpha_y", mapped.alpha_y},
          {"complex_fresnel", mapped.complex_fresnel},
          {"eta", vec(mapped.eta)},  // conductors with complex_fresnel: eta + i k per RGB
          {"k", vec(mapped.k)},
          {"ior", mapped.ior},
          {"metallic", m.metallic},
          {"transmission", m.transmission},
          {"anisotropy", m.anisotropy},
          {"film_thickness", m.film_thickness},
          // Texture names ("" for none), the mapping a roughness texture's value goes
          // through, and RayON's pattern (kind null for none), as the renderer reads them.
          {"roughness_mapping", mapped.roughness_mapping == RoughnessMapping::kHalf      ? "half"
                                : mapped.roughness_mapping == RoughnessMapping::kSquared ? "squared"
                                                                                         : "none"},
          {"albedo_texture", m.albedo_texture},
          {"roughness_texture", m.roughness_texture},
          {"pattern", m.pattern ? json(m.pattern->type) : json(nullptr)},
          {"pattern_color", vec(mapped.pattern.color)},
          {"pattern_dot_count", mapped.pattern.dot_count},
          {"pattern_cos_dot_radius", mapped.pattern.cos_dot_radius}};
}

// Row-major, as Blender's Matrix() takes rows; glm stores columns.
json matrix_json(const std::optional<TransformDesc>& transform) {
  if (!transform) return nullptr;
  const glm::dmat4 m = transform->matrix();
  json rows = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) rows.push_back(m[c][r]);
  return rows;
}

template <typename Shape>
json common(const char* type, const Shape& s) {
  return {{"type", type},
          {"material", s.material},
          {"visible", s.visible},
          {"source_index", s.source_index},
          {"matrix", matrix_json(s.transform)}};
}

template <typename Shape>
json unsupported(const char* kind, const Shape& s) {
  json j = common("unsupported", s);
  j["kind"] = kind;
  return j;
}

// A float EXR of `width` x `height` linear RGB pixels (alpha 1).
void write_rgb(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
               const std::vector<float>& rgb) {
  const std::size_t pixels = std::size_t{width} * height;
  RgbaImage image{width, height, std::vector<float>(pixels * 4, 1.0f)};
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) image.pixels[p * 4 + c] = rgb[p * 3 + c];
  write_image(path, image);
}

json mesh_json(const TriangleMeshDesc& mesh) {
  json j = common("mesh", mesh);
  std::vector<double> positions, normals;
  positions.reserve(mesh.positions.size() * 3);
  for (const auto& p : mesh.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
  normals.reserve(mesh.normals.size() * 3);
  for (const auto& n : mesh.normals) normals.insert(normals.end(), {n.x, n.y, n.z});
  j["positions"] = std::move(positions);
  j["indices"] = mesh.indices;
  j["normals"] = std::move(normals);
  std::vector<double> uvs;
  uvs.reserve(mesh.uvs.size() * 2);
  for (const auto& uv : mesh.uvs) uvs.insert(uvs.end(), {uv.x, uv.y});
  j["uvs"] = std::move(uvs);  // empty, or one pair per position
  j["source_file"] = mesh.source_file;
  return j;
}

}  // namespace

std::string scene_to_json(const SceneDescription& scene) {
  json shapes = json::array();
  for (const auto& s : scene.spheres) {
    json j = common("sphere", s);
    j["center"] = vec(s.center);
    j["radius"] = s.radius;
    shapes.push_back(std::move(j));
  }
  // RayON's golf balls: the sphere, with how far its dimples tilt the normal (the peer draws
  // the plain sphere).
  for (const auto& d : scene.displaced_spheres) {
    json j = common("sphere", d);
    j["center"] = vec(d.center);
    j["radius"] = d.radius;
    j["dimples"] = d.displacement_scale;
    shapes.push_back(std::move(j));
  }
  for (const auto& q : scene.quads) {
    json j = common("quad", q);
    j["corner"] = vec(q.corner);
    j["u"] = vec(q.u);
    j["v"] = vec(q.v);
    shapes.push_back(std::move(j));
  }
  for (const auto& d : scene.disks) {
    json j = common("disk", d);
    j["center"] = vec(d.center);
    j["normal"] = vec(d.normal);
    j["radius"] = d.radius;
    j["inner_radius"] = d.inner_radius;
    shapes.push_back(std::move(j));
  }
  for (const auto& p : scene.planes) {
    json j = common("plane", p);
    j["point"] = vec(p.point);
    j["normal"] = vec(p.normal);
    shapes.push_back(std::move(j));
  }
  for (const auto& m : scene.meshes) shapes.push_back(mesh_json(m));
  for (const auto& c : scene.cylinders) {
    json j = common("cylinder", c);
    j["base"] = vec(c.base);
    j["axis"] = vec(c.axis);
    j["radius"] = c.radius;
    j["height"] = c.height;
    j["caps"] = c.caps;
    shapes.push_back(std::move(j));
  }
  for (const auto& c : scene.cones) {
    json j = common("cone", c);
    j["base"] = vec(c.base);
    j["axis"] = vec(c.axis);
    j["base_radius"] = c.base_radius;
    j["top_radius"] = c.top_radius;
    j["height"] = c.height;
    j["caps"] = c.caps;
    shapes.push_back(std::move(j));
  }
  for (const auto& t : scene.tori) {
    json j = common("torus", t);
    j["center"] = vec(t.center);
    j["axis"] = vec(t.axis);
    j["major_radius"] = t.major_radius;
    j["minor_radius"] = t.minor_radius;
    shapes.push_back(std::move(j));
  }
  for (const auto& s : scene.sdf_boxes) shapes.push_back(unsupported("sdf_box", s));
  for (const auto& s : scene.sdf_tori) shapes.push_back(unsupported("sdf_torus", s));
  for (const auto& s : scene.sdf_capsules) shapes.push_back(unsupported("sdf_capsule", s));
  for (const auto& s : scene.patches) shapes.push_back(unsupported("patch", s));
  for (const auto& s : scene.trimmed_faces) shapes.push_back(unsupported("trimmed_face", s));

  json materials = json::array();
  for (const auto& m : scene.materials) materials.push_back(material_json(m));

  // Textures as the renderer reads them; an image's decoded linear pixels go into a file
  // beside the JSON (write_scene_json), named here.
  json textures = json::array();
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const TextureDesc& t = scene.textures[i];
    textures.push_back(
        {{"name", t.name},
         {"type", t.type},
         {"scale", t.scale},
         {"color_a", vec(t.color_a)},
         {"color_b", vec(t.color_b)},
         {"wrap", t.wrap},
         {"filter", t.filter},
         {"image", t.type == "image" ? json(texture_image_name(i)) : json(nullptr)}});
  }

  json lights = json::array();
  for (const LightDesc& l : scene.lights)
    lights.push_back({{"type", l.type == "sun" ? "directional" : l.type},
                      {"position", vec(l.position)},
                      {"direction", vec(l.direction)},
                      {"color", vec(l.color)},
                      {"intensity", l.intensity},
                      {"irradiance", l.irradiance},
                      {"cone_angle_degrees", l.cone_angle_degrees},
                      {"cone_falloff_degrees", l.cone_falloff_degrees},
                      {"angular_radius_degrees", l.angular_radius_degrees}});
  // What an escaping ray sees: the environment when the scene has one, else the background
  // colour (a constant environment). An image's pixels go into a file beside the JSON
  // (write_scene_json), named here.
  json environment = {{"type", "constant"},
                      {"color", vec(scene.background.color)},
                      {"intensity", scene.background.intensity},
                      {"rotation_degrees", 0.0},
                      {"image", nullptr}};
  if (scene.environment) {
    const EnvironmentDesc& e = *scene.environment;
    environment = {{"type", e.type},
                   {"color", vec(e.color)},
                   {"intensity", e.intensity},
                   {"rotation_degrees", e.rotation_degrees},
                   {"image", e.type == "image" ? json(kEnvironmentImageName) : json(nullptr)}};
  }

  const json out = {
      {"format", "tessera-scene-export"},
      {"version", 1},
      {"camera",
       {{"position", vec(scene.camera.position)},
        {"look_at", vec(scene.camera.look_at)},
        {"up", vec(scene.camera.up)},
        {"fov_degrees", scene.camera.fov_degrees}}},
      {"background",
       {{"color", vec(scene.background.color)}, {"intensity", scene.background.intensity}}},
      {"render",
       {{"width", scene.render.width},
        {"height", scene.render.height},
        {"max_depth", scene.render.max_depth},
        {"seed", scene.render.seed},
        {"integrator", to_string(scene.render.integrator)}}},
      {"environment", std::move(environment)},
      {"lights", std::move(lights)},
      {"materials", std::move(materials)},
      {"textures", std::move(textures)},
      {"shapes", std::move(shapes)}};
  return out.dump();
}

void write_scene_json(const SceneDescription& scene, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  out << scene_to_json(scene);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  // The pixels the renderer read (linear RGB, rows from the top down), so the peer neither
  // reads the original files nor converts their colour space again.
  if (scene.environment && scene.environment->type == "image") {
    const EnvironmentDesc& e = *scene.environment;
    write_rgb(path.parent_path() / kEnvironmentImageName, e.image_width, e.image_height,
              e.image_pixels);
  }
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const TextureDesc& t = scene.textures[i];
    if (t.type == "image")
      write_rgb(path.parent_path() / texture_image_name(i), t.image_width, t.image_height,
                t.image_pixels);
  }
}

std::string texture_image_name(std::size_t index) {
  return "texture_" + std::to_string(index) + ".exr";
}

}  // namespace tessera::bench
