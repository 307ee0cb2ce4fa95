#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tessera {

// The neutral, double-precision description of a scene, built from YAML or protobuf and
// turned into the float render scene once per job.

struct CameraDesc {
  glm::dvec3 position{0.0, 0.0, 5.0};
  glm::dvec3 look_at{0.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov_degrees = 40.0;  // vertical field of view
};

struct BackgroundDesc {
  glm::dvec3 color{0.0};
  double intensity = 1.0;  // radiance of a miss = color * intensity
};

enum class MaterialType {
  kLambertian,
  kLight,
  kMetal,
  kRoughMirror,
  kGlass,
  kAnisotropicMetal,
  kClearCoat,
  kThinFilm,
};

const char* to_string(MaterialType type);
std::optional<MaterialType> material_type_from_string(const std::string& name);

struct MaterialDesc {
  std::string name;
  MaterialType type = MaterialType::kLambertian;
  glm::dvec3 albedo{0.8};
  glm::dvec3 emission{0.0};
  double roughness = 0.0;
  double refractive_index = 1.5;
  double metallic = 0.0;
  double transmission = 0.0;
  double anisotropy = 0.0;
  std::string preset;           // anisotropic_metal: named metal colour
  double film_thickness = 0.0;  // thin_film, nanometres
  double film_ior = 1.33;
};

// Every shape remembers where it came from in the input (`geometry[i]`), so a problem found
// after parsing still names the field the user wrote.
struct SphereDesc {
  glm::dvec3 center{0.0};
  double radius = 1.0;
  std::uint32_t material = 0;
  bool visible = true;  // false: emits light but is not seen by camera rays
  std::uint32_t source_index = 0;
};

struct QuadDesc {
  glm::dvec3 corner{0.0};
  glm::dvec3 u{1.0, 0.0, 0.0};
  glm::dvec3 v{0.0, 1.0, 0.0};
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
};

struct TriangleMeshDesc {
  std::vector<glm::dvec3> positions;
  std::vector<std::uint32_t> indices;  // three per triangle
  // Optional per-vertex data from mesh files: empty, or one entry per position.
  std::vector<glm::dvec3> normals;
  std::vector<glm::dvec2> uvs;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::string source_file;  // mesh file it was loaded from, if any
};

// The program set a job renders with.
enum class IntegratorKind {
  kPath,          // path tracing with next-event estimation (the beauty render)
  kNormals,       // first-hit shading normals mapped to [0, 1]
  kShadow,        // direct light only, any-hit shadow rays
  kTransparency,  // all hits along the camera ray composited front to back
  kAlbedo,        // first-hit albedo
  kDepth,         // first-hit distance
};
const char* to_string(IntegratorKind kind);
std::optional<IntegratorKind> integrator_from_string(const std::string& name);

// Arbitrary output variables a job may ask for besides the beauty pass.
enum AovBit : std::uint32_t {
  kAovAlbedo = 1u << 0,
  kAovNormal = 1u << 1,
  kAovDepth = 1u << 2,
  kAovPrimitiveId = 1u << 3,
};
inline constexpr std::uint32_t kAllAovs = kAovAlbedo | kAovNormal | kAovDepth | kAovPrimitiveId;
inline constexpr const char* kAovNames[] = {"albedo", "normal", "depth", "primitive_id"};
std::optional<AovBit> aov_from_string(const std::string& name);

struct RenderSettings {
  std::uint32_t width = 320;
  std::uint32_t height = 240;
  std::uint32_t samples_per_pixel = 16;
  std::uint32_t max_depth = 6;
  std::uint32_t tile_size = 32;
  std::uint64_t seed = 0;
  IntegratorKind integrator = IntegratorKind::kPath;
  std::uint32_t aovs = 0;  // AovBit mask; only the path integrator produces AOVs
};

struct SceneDescription {
  CameraDesc camera;
  BackgroundDesc background;
  std::vector<MaterialDesc> materials;
  std::vector<SphereDesc> spheres;
  std::vector<QuadDesc> quads;
  std::vector<TriangleMeshDesc> meshes;
  RenderSettings render;

  std::size_t triangle_count() const;
  // Index of the material called `name`, if any.
  std::optional<std::uint32_t> find_material(const std::string& name) const;
};

// Limits that keep one job from exhausting the daemon; they apply to every input path.
struct SceneLimits {
  std::uint32_t max_dimension = 16384;
  std::uint32_t max_samples_per_pixel = 65536;
  std::uint32_t max_depth = 64;
  std::uint32_t min_tile_size = 8;
  std::uint32_t max_tile_size = 1024;
  std::size_t max_triangles = 50'000'000;
};

// Semantic checks shared by every loader (finite numbers, positive radii, valid material
// references, render settings in range). Returns every issue found, field paths filled,
// file and line left empty for the caller to add.
std::vector<struct SceneIssue> validate_scene(const SceneDescription& scene,
                                              const SceneLimits& limits = {});

}  // namespace tessera
