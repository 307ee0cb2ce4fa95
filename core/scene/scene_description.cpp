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
// Indexed by the enums' values: the one list of each set of names. The protobuf enums
// follow the same order and names (MATERIAL_TYPE_<NAME>, INTEGRATOR_<NAME>, AOV_<NAME>,
// SAMPLER_<NAME>, LIGHT_STRATEGY_<NAME>).
constexpr std::string_view kMaterialTypeNames[] = {
    "lambertian", "light",     "metal",  "rough_mirror", "glass",        "anisotropic_metal",
    "clear_coat", "thin_film", "mirror", "constant",     "show_normals",
};
constexpr std::string_view kIntegratorNames[] = {"path",   "normals", "shadow", "transparency",
                                                 "albedo", "depth",   "phong"};
constexpr std::string_view kAovNameViews[] = {"albedo",       "normal",   "depth",
                                              "primitive_id", "variance", "sample_count"};
constexpr std::string_view kSamplerNames[] = {"independent", "sobol"};
constexpr std::string_view kLightStrategyNames[] = {"mis", "light", "bsdf"};
constexpr std::string_view kRenderDeviceNames[] = {"any", "cpu", "gpu"};
static_assert(std::size(kRenderDeviceNames) == static_cast<std::size_t>(RenderDevice::kGpu) + 1);
static_assert(std::size(kMaterialTypeNames) ==
              static_cast<std::size_t>(MaterialType::kShowNormals) + 1);
static_assert(std::size(kIntegratorNames) == static_cast<std::size_t>(IntegratorKind::kPhong) + 1);
static_assert(std::size(kSamplerNames) == static_cast<std::size_t>(SamplerKind::kSobol) + 1);
static_assert(std::size(kLightStrategyNames) == static_cast<std::size_t>(LightStrategy::kBsdf) + 1);

template <typename Enum, std::size_t N>
std::optional<Enum> from_name(const std::string_view (&names)[N], const std::string& name) {
  for (std::size_t i = 0; i < N; ++i)
    if (names[i] == name) return static_cast<Enum>(i);
  return std::nullopt;
}
}  // namespace

const char* to_string(MaterialType type) {
  const auto i = static_cast<std::size_t>(type);
  return i < std::size(kMaterialTypeNames) ? kMaterialTypeNames[i].data() : "unknown";
}

std::optional<MaterialType> material_type_from_string(const std::string& name) {
  // RayON's other spellings of a type (YAML only: protobuf has one enum value per type).
  if (name == "dielectric") return MaterialType::kGlass;
  return from_name<MaterialType>(kMaterialTypeNames, name);
}

std::span<const std::string_view> material_type_names() {
  return kMaterialTypeNames;
}

void apply_type_defaults(MaterialDesc& material) {
  switch (material.type) {
    case MaterialType::kLight:
    case MaterialType::kGlass:
    case MaterialType::kAnisotropicMetal:
      material.albedo = glm::dvec3(1.0);
      break;
    case MaterialType::kThinFilm:
      // RayON's thin film: 400 nm thick, in air (refractive_index is the medium around it).
      material.film_thickness = 400.0;
      material.refractive_index = 1.0;
      break;
    default:
      break;
  }
}

const char* to_string(IntegratorKind kind) {
  const auto i = static_cast<std::size_t>(kind);
  return i < std::size(kIntegratorNames) ? kIntegratorNames[i].data() : "unknown";
}

std::optional<IntegratorKind> integrator_from_string(const std::string& name) {
  return from_name<IntegratorKind>(kIntegratorNames, name);
}

std::span<const std::string_view> integrator_names() {
  return kIntegratorNames;
}

const char* to_string(SamplerKind kind) {
  const auto i = static_cast<std::size_t>(kind);
  return i < std::size(kSamplerNames) ? kSamplerNames[i].data() : "unknown";
}

std::optional<SamplerKind> sampler_from_string(const std::string& name) {
  return from_name<SamplerKind>(kSamplerNames, name);
}

std::span<const std::string_view> sampler_names() {
  return kSamplerNames;
}

const char* to_string(LightStrategy strategy) {
  const auto i = static_cast<std::size_t>(strategy);
  return i < std::size(kLightStrategyNames) ? kLightStrategyNames[i].data() : "unknown";
}

std::optional<LightStrategy> light_strategy_from_string(const std::string& name) {
  return from_name<LightStrategy>(kLightStrategyNames, name);
}

std::span<const std::string_view> light_strategy_names() {
  return kLightStrategyNames;
}

const char* to_string(RenderDevice device) {
  const auto i = static_cast<std::size_t>(device);
  return i < std::size(kRenderDeviceNames) ? kRenderDeviceNames[i].data() : "unknown";
}

std::optional<RenderDevice> render_device_from_string(const std::string& name) {
  return from_name<RenderDevice>(kRenderDeviceNames, name);
}

std::span<const std::string_view> render_device_names() {
  return kRenderDeviceNames;
}

std::optional<AovBit> aov_from_string(const std::string& name) {
  for (std::uint32_t i = 0; i < std::size(kAovNameViews); ++i)
    if (name == kAovNameViews[i]) return static_cast<AovBit>(1u << i);
  return std::nullopt;
}

std::span<const std::string_view> aov_names() {
  return kAovNameViews;
}

std::string joined(std::span<const std::string_view> names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += names[i];
  }
  return text;
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
  return spheres.size() + displaced_spheres.size() + quads.size() + planes.size() + disks.size() +
         cylinders.size() + cones.size() + tori.size() + sdf_boxes.size() + sdf_tori.size() +
         sdf_capsules.size() + patches.size() + trimmed_faces.size();
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

}  // namespace tessera
