#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "tessera/math/sampler_kind.hpp"
#include "tessera/scene/schema/path_style.hpp"

namespace tessera {

// The neutral, double-precision description of a scene, built from YAML or protobuf and
// turned into the float render scene once per job.

struct CameraDesc {
  glm::dvec3 position{0.0, 0.0, 5.0};
  glm::dvec3 look_at{0.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov_degrees = 40.0;     // vertical field of view
  std::string projection;        // "perspective" (also when empty) or "orthographic"
  double ortho_height = 0.0;     // orthographic: the image's height in world units; 0: the
                                 // perspective view's height at look_at
  double aperture_radius = 0.0;  // thin lens radius, world units; 0: pinhole
  double focus_distance = 0.0;   // sharp plane's distance along the view; 0: at look_at

  friend bool operator==(const CameraDesc&, const CameraDesc&) = default;
};

struct BackgroundDesc {
  glm::dvec3 color{0.0};
  double intensity = 1.0;  // radiance of a miss = color * intensity

  friend bool operator==(const BackgroundDesc&, const BackgroundDesc&) = default;
};

// A light that is not a shape (YAML `lights`, protobuf `Scene.lights`). Which fields apply
// depends on the type: point (position, intensity), spot (position, direction, intensity,
// cone_angle_degrees, cone_falloff_degrees), directional or its alias sun (direction,
// irradiance, angular_radius_degrees). Colours multiply intensity and irradiance.
struct LightDesc {
  std::string type = "point";  // point, spot, directional, sun
  glm::dvec3 position{0.0};
  glm::dvec3 direction{0.0, -1.0, 0.0};  // spot: where it shines; directional: where light travels
  glm::dvec3 color{1.0};
  double intensity = 1.0;               // point, spot: radiant intensity, W/sr (times color)
  double irradiance = 1.0;              // directional: W/m^2 on a surface facing it (times color)
  double cone_angle_degrees = 30.0;     // spot: half-angle where the light ends
  double cone_falloff_degrees = 5.0;    // spot: width of the smooth edge, inside the cone
  double angular_radius_degrees = 0.0;  // directional: 0 = a delta direction; the sun ~0.27

  friend bool operator==(const LightDesc&, const LightDesc&) = default;
};

// What an escaping ray sees (YAML and protobuf `environment`). Absent, the background is
// the constant environment. `gradient` is RayON's sky: white below to (0.5, 0.7, 1.0) above,
// times intensity (color is not used). `image`: an equirectangular image (YAML `file`, read
// when the scene is loaded; protobuf carries its pixels), times color and intensity.
struct EnvironmentDesc {
  std::string type = "constant";  // constant, gradient, image
  glm::dvec3 color{1.0};
  double intensity = 1.0;
  std::string file{};             // YAML, image: the file it was read from
  double rotation_degrees = 0.0;  // image: turned about +y
  std::uint32_t image_width = 0, image_height = 0;
  std::vector<float> image_pixels{};  // linear RGB, rows from the zenith down

  friend bool operator==(const EnvironmentDesc&, const EnvironmentDesc&) = default;
};

// A texture materials may take for their albedo or roughness: an image (read through
// OpenImageIO into linear RGB floats where the scene is loaded; over protobuf its pixels
// travel inline) or a procedural checker. Looked up by the surface's uv.
struct TextureDesc {
  std::string name;
  std::string type;                  // image, checker
  std::string file{};                // YAML, image: the file it was read from
  std::string color_space = "auto";  // image file: srgb, linear, auto (8/16-bit sRGB, float linear)
  std::string wrap = "repeat";       // repeat, clamp, mirror
  std::string filter = "trilinear";  // trilinear (mipmapped), bilinear, nearest
  double scale = 1.0;                // repeats per unit of uv
  glm::dvec3 color_a{0.9};           // checker
  glm::dvec3 color_b{0.1};
  std::uint32_t image_width = 0, image_height = 0;
  std::vector<float> image_pixels{};  // linear RGB, rows from the top (v = 1) down

  friend bool operator==(const TextureDesc&, const TextureDesc&) = default;
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
  kMirror,       // RayON: perfect specular reflection tinted by albedo
  kConstant,     // RayON: flat unlit colour (albedo); the path ends there
  kShowNormals,  // RayON: the surface normal as a colour; the path ends there
};

const char* to_string(MaterialType type);
std::optional<MaterialType> material_type_from_string(const std::string& name);
std::span<const std::string_view> material_type_names();  // in MaterialType order

// RayON's procedural pattern on a material's albedo. fibonacci_dots paints `color` dots of
// angular radius `dot_radius` (radians) around `dot_count` points of a spherical Fibonacci
// spiral, seen from a sphere's centre (from the world origin on other shapes). RayON parses
// checkerboard and stripes but draws them as the plain albedo, and so does Tessera.
struct PatternDesc {
  std::string type;  // fibonacci_dots, checkerboard, stripes
  glm::dvec3 color{0.0};
  std::uint32_t dot_count = 0;
  double dot_radius = 0.0;

  friend bool operator==(const PatternDesc&, const PatternDesc&) = default;
};

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
  std::string preset;   // conductors: named measured metal (its eta and k)
  glm::dvec3 eta{0.0};  // conductors: complex index eta + i k per RGB; 0 = unset
  glm::dvec3 k{0.0};
  // glass: Beer's law, the share of light left after `transmittance_distance` inside.
  glm::dvec3 transmittance{1.0};
  double transmittance_distance = 1.0;
  double film_thickness = 0.0;  // thin_film, nanometres (400 for thin_film by default)
  double film_ior = 1.33;
  // RayON's emission shorthand: emitted radiance color * emission_intensity, instead of
  // `emission` (validation rejects both together).
  glm::dvec3 color{1.0};
  double emission_intensity = 0.0;
  std::optional<PatternDesc> pattern = std::nullopt;
  // Names of textures (SceneDescription::textures) that give the albedo or the roughness
  // (the mean of the texel's RGB) at each hit instead of the constants above; empty: none.
  std::string albedo_texture{};
  std::string roughness_texture{};

  // What the material emits, whichever way it was written.
  glm::dvec3 emitted_radiance() const { return emission + color * emission_intensity; }

  friend bool operator==(const MaterialDesc&, const MaterialDesc&) = default;
};

// Defaults that depend on the type, applied before the fields are read: a light's albedo
// is 1 (its emission is what it shows); so is glass's (lossless unless tinted) and an
// anisotropic metal's (its colour comes from its preset or eta and k); a thin film is
// 400 nm thick and in air (refractive_index 1), as in RayON.
void apply_type_defaults(MaterialDesc& material);

// Placement of one geometry entry: p -> translate + rotate(scale * p), i.e. scale first,
// then rotate by `rotate_degrees` around `rotate_axis` (right-handed), then translate.
// The renderer bakes it into the shape where the shape type can represent the result and
// instances the shape otherwise.
struct TransformDesc {
  glm::dvec3 translate{0.0};
  glm::dvec3 rotate_axis{0.0, 0.0, 1.0};  // any non-zero length
  double rotate_degrees = 0.0;
  glm::dvec3 scale{1.0};  // per axis; non-zero

  bool uniform_scale() const { return scale.x == scale.y && scale.y == scale.z; }
  // The affine map as a 4x4 matrix (column-major, glm).
  glm::dmat4 matrix() const;
  friend bool operator==(const TransformDesc&, const TransformDesc&) = default;
};

// Every shape remembers where it came from in the input (`geometry[i]`), so a problem found
// after parsing still names the field the user wrote. `transform`, when set, places the
// shape as written (object space -> world space).
struct SphereDesc {
  glm::dvec3 center{0.0};
  double radius = 1.0;
  std::uint32_t material = 0;
  bool visible = true;  // false: emits light but is not seen by camera rays
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const SphereDesc&, const SphereDesc&) = default;
};

// RayON's displaced_sphere: a sphere shaded with golf-ball dimples (render/golf_dimples.hpp).
struct DisplacedSphereDesc {
  glm::dvec3 center{0.0};
  double radius = 1.0;
  double displacement_scale = 0.2;  // how far the dimples tilt the normal
  std::uint32_t pattern_type = 0;   // 0: golf-ball dimples, RayON's only pattern
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const DisplacedSphereDesc&, const DisplacedSphereDesc&) = default;
};

struct QuadDesc {
  glm::dvec3 corner{0.0};
  glm::dvec3 u{1.0, 0.0, 0.0};
  glm::dvec3 v{0.0, 1.0, 0.0};
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const QuadDesc&, const QuadDesc&) = default;
};

// Infinite plane through `point` perpendicular to `normal`. Never an emitter (it would have
// infinite power); kept out of the BVH and tested per ray.
struct PlaneDesc {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0, 1.0, 0.0};  // non-zero; normalised by the renderer
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const PlaneDesc&, const PlaneDesc&) = default;
};

// Disk of `radius` around `center`, perpendicular to `normal`; an annulus when
// inner_radius > 0.
struct DiskDesc {
  glm::dvec3 center{0.0};
  glm::dvec3 normal{0.0, 1.0, 0.0};
  double radius = 1.0;
  double inner_radius = 0.0;  // [0, radius)
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const DiskDesc&, const DiskDesc&) = default;
};

// Finite cylinder from `base` to base + height * axis / |axis|; caps close both ends.
struct CylinderDesc {
  glm::dvec3 base{0.0};
  glm::dvec3 axis{0.0, 1.0, 0.0};
  double radius = 1.0;
  double height = 1.0;
  bool caps = false;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const CylinderDesc&, const CylinderDesc&) = default;
};

// Finite cone (one nappe): base_radius at `base`, top_radius (0: pointed) at the top.
struct ConeDesc {
  glm::dvec3 base{0.0};
  glm::dvec3 axis{0.0, 1.0, 0.0};
  double base_radius = 1.0;
  double top_radius = 0.0;
  double height = 1.0;
  bool caps = false;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const ConeDesc&, const ConeDesc&) = default;
};

// Torus around `axis` through `center`: ring (minor < major), horn (=) or spindle (>).
struct TorusDesc {
  glm::dvec3 center{0.0};
  glm::dvec3 axis{0.0, 1.0, 0.0};
  double major_radius = 1.0;
  double minor_radius = 0.25;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const TorusDesc&, const TorusDesc&) = default;
};

// Signed-distance primitives, drawn by sphere tracing.
// Axis-aligned box of half extents `half_extent`; rounding > 0 rounds its edges (a rounded
// box, same outer size). YAML `sdf_box` and `sdf_rounded_box` both map here.
struct SdfBoxDesc {
  glm::dvec3 center{0.0};
  glm::dvec3 half_extent{0.5};
  double rounding = 0.0;  // [0, smallest half extent]
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const SdfBoxDesc&, const SdfBoxDesc&) = default;
};

// Ring torus (minor < major) as a distance function.
struct SdfTorusDesc {
  glm::dvec3 center{0.0};
  glm::dvec3 axis{0.0, 1.0, 0.0};
  double major_radius = 1.0;
  double minor_radius = 0.25;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const SdfTorusDesc&, const SdfTorusDesc&) = default;
};

// Points within `radius` of the segment a-b.
struct SdfCapsuleDesc {
  glm::dvec3 a{0.0};
  glm::dvec3 b{0.0, 1.0, 0.0};
  double radius = 0.25;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const SdfCapsuleDesc&, const SdfCapsuleDesc&) = default;
};

// Bicubic B-spline patch; rational (NURBS) when `weights` is set. Control point (i, j), i
// along u and j along v, is control_points[i * count_v + j]. Knot vectors hold count + 4
// non-decreasing values each; empty means clamped uniform over [0, 1] (the patch then
// passes through its four corner points). The patch covers [knots[3], knots[count]] in each
// direction, and that is its uv (trimming loops of a trimmed patch use it). A transform is
// baked into the control points exactly (B-splines are affine invariant).
struct SplinePatchDesc {
  std::uint32_t count_u = 4;
  std::uint32_t count_v = 4;
  std::vector<glm::dvec3> control_points;
  std::vector<double> weights;  // empty: non-rational; else one per control point, > 0
  std::vector<double> knots_u;  // empty: clamped uniform
  std::vector<double> knots_v;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const SplinePatchDesc&, const SplinePatchDesc&) = default;
};

// The clamped uniform knot vector of a cubic with `count` control points over [0, 1]:
// four zeros, count - 4 evenly spaced inner knots, four ones.
std::vector<double> clamped_uniform_knots(std::uint32_t count);

// The surface a trimmed face cuts: one of the analytic surfaces or a patch. Its own
// material, visible and transform fields are ignored (the face's apply).
using TrimmedSurfaceDesc = std::variant<PlaneDesc, DiskDesc, QuadDesc, SphereDesc, CylinderDesc,
                                        ConeDesc, TorusDesc, SplinePatchDesc>;
const char* trimmed_surface_name(const TrimmedSurfaceDesc& surface);  // "sphere", "patch", ...

// A surface bounded in its own uv (surface_at's uv, see the README) by closed loops:
// loops[0] the outer boundary, the others holes; points inside by non-zero winding. Each
// loop is a polyline of >= 3 uv points, the last joined back to the first; on a surface
// whose u (or v) wraps, steps are taken the short way round, so loops may cross the seam.
struct TrimmedFaceDesc {
  TrimmedSurfaceDesc surface = SphereDesc{};
  std::vector<std::vector<glm::dvec2>> loops;
  std::uint32_t material = 0;
  bool visible = true;
  std::uint32_t source_index = 0;
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const TrimmedFaceDesc&, const TrimmedFaceDesc&) = default;
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
  std::optional<TransformDesc> transform = std::nullopt;

  friend bool operator==(const TriangleMeshDesc&, const TriangleMeshDesc&) = default;
};

// The mesh moved by `transform`: positions mapped, normals by the inverse transpose
// (renormalised), so shading stays right under non-uniform scale. `transform` of the
// result is left as the input's.
TriangleMeshDesc transformed_mesh(const TriangleMeshDesc& mesh, const TransformDesc& transform);

// The program set a job renders with.
enum class IntegratorKind {
  kPath,          // path tracing with next-event estimation (the beauty render)
  kNormals,       // first-hit shading normals mapped to [0, 1]
  kShadow,        // direct light only, any-hit shadow rays
  kTransparency,  // all hits along the camera ray composited front to back
  kAlbedo,        // first-hit albedo
  kDepth,         // first-hit distance
  kPhong,         // first-hit Blinn-Phong shading under a headlight: fast CAD views
};
const char* to_string(IntegratorKind kind);
std::optional<IntegratorKind> integrator_from_string(const std::string& name);
std::span<const std::string_view> integrator_names();  // in IntegratorKind order

// The random sequence the renderer draws from (SamplerKind is declared in
// math/sampler_kind.hpp, which the CUDA-side rng.hpp includes without scene headers).
const char* to_string(SamplerKind kind);
std::optional<SamplerKind> sampler_from_string(const std::string& name);
std::span<const std::string_view> sampler_names();  // in SamplerKind order

// Which estimators of direct light the path tracer combines. A plain enum beside the
// settings (this header already reaches the path tracer), so TESSERA_HD code can take it.
enum class LightStrategy : std::uint32_t {
  kMis,    // light samples and BSDF samples, weighted by multiple importance sampling
  kLight,  // next-event estimation only: emitters hit by scattered rays count only after
           // camera rays and specular bounces
  kBsdf,   // no light sampling: emitters count when a scattered ray hits them (hidden
           // emitters, which no ray can hit, are still light-sampled)
};
const char* to_string(LightStrategy strategy);
std::optional<LightStrategy> light_strategy_from_string(const std::string& name);
std::span<const std::string_view> light_strategy_names();  // in LightStrategy order

// Where a daemon may render a job's tiles: any worker, the CPU threads alone, or its GPUs
// alone (a GPU job the daemon's GPUs cannot render fails, saying why).
enum class RenderDevice : std::uint32_t { kAny, kCpu, kGpu };
const char* to_string(RenderDevice device);
std::optional<RenderDevice> render_device_from_string(const std::string& name);
std::span<const std::string_view> render_device_names();  // in RenderDevice order

// Arbitrary output variables a job may ask for besides the beauty pass.
enum AovBit : std::uint32_t {
  kAovAlbedo = 1u << 0,
  kAovNormal = 1u << 1,
  kAovDepth = 1u << 2,
  kAovPrimitiveId = 1u << 3,
  kAovVariance = 1u << 4,     // the variance of the pixel's mean luminance (adaptive sampling's
                              // error estimate), in R, G and B
  kAovSampleCount = 1u << 5,  // samples the pixel took, in R, G and B
};
inline constexpr std::size_t kAovCount = 6;
inline constexpr std::uint32_t kAllAovs =
    kAovAlbedo | kAovNormal | kAovDepth | kAovPrimitiveId | kAovVariance | kAovSampleCount;
std::optional<AovBit> aov_from_string(const std::string& name);
std::span<const std::string_view> aov_names();  // bit i is aov_names()[i]

// "a, b, c or d", for messages that list the accepted values.
std::string joined(std::span<const std::string_view> names);

struct RenderSettings {
  std::uint32_t width = 320;
  std::uint32_t height = 240;
  std::uint32_t samples_per_pixel = 16;
  std::uint32_t max_depth = 16;  // RayON's depth, so its scenes render alike
  std::uint32_t tile_size = 32;
  std::uint64_t seed = 0;
  IntegratorKind integrator = IntegratorKind::kPath;
  std::uint32_t aovs = 0;  // AovBit mask; only the path integrator produces AOVs
  SamplerKind sampler = SamplerKind::kSobol;
  LightStrategy light_strategy = LightStrategy::kMis;
  RenderDevice device = RenderDevice::kAny;
  // Camera rays that miss leave RGB 0 as well as alpha 0 (Cycles' "transparent film"), so
  // the image composites over a plate; the background still lights the scene.
  bool transparent_background = false;
  // Cycles' indirect light clamp: the largest value any colour component of one sample's
  // indirect light (everything after the first bounce) may add; 0 = off.
  double clamp = 0.0;
  std::string pixel_filter;   // "box" (also when empty), "gaussian" or "blackman_harris"
  double filter_width = 0.0;  // pixels; 0: the filter's default (box 1, others 3)
  // Adaptive sampling: 0 renders samples_per_pixel everywhere; otherwise a pixel stops once
  // the relative standard error of its mean luminance is below this (samples_per_pixel is
  // then the most a pixel takes).
  double target_error = 0.0;
  std::uint32_t min_samples_per_pixel = 16;  // before adaptive sampling may stop a pixel
  // Progressive passes: the daemon renders samples_per_pixel in this many passes over the
  // whole image, each tile's passes adding up to the single-pass image bit for bit (0 or 1:
  // one pass). Not with adaptive sampling.
  std::uint32_t passes = 1;
  // How the triangles' acceleration structure is built: "auto" (also when empty; chosen per
  // mesh from its size and how well its triangles fill their boxes), "spatial" (spatial
  // splits for every mesh, whatever its size or its triangles' shape) or "binned" (the binned
  // surface-area build alone: the shortest build, for previews). Only speed and memory
  // change, never the image.
  std::string accel_builder;

  bool adaptive() const { return target_error > 0.0; }
  std::uint32_t pass_count() const { return passes == 0 ? 1 : passes; }

  friend bool operator==(const RenderSettings&, const RenderSettings&) = default;
};

struct SceneDescription {
  CameraDesc camera;
  BackgroundDesc background;
  std::optional<EnvironmentDesc> environment;  // set: replaces the background
  std::vector<LightDesc> lights;
  std::vector<TextureDesc> textures;
  std::vector<MaterialDesc> materials;
  std::vector<SphereDesc> spheres;
  std::vector<DisplacedSphereDesc> displaced_spheres;
  std::vector<QuadDesc> quads;
  std::vector<TriangleMeshDesc> meshes;
  std::vector<PlaneDesc> planes;
  std::vector<DiskDesc> disks;
  std::vector<CylinderDesc> cylinders;
  std::vector<ConeDesc> cones;
  std::vector<TorusDesc> tori;
  std::vector<SdfBoxDesc> sdf_boxes;
  std::vector<SdfTorusDesc> sdf_tori;
  std::vector<SdfCapsuleDesc> sdf_capsules;
  std::vector<SplinePatchDesc> patches;
  std::vector<TrimmedFaceDesc> trimmed_faces;
  RenderSettings render;

  std::size_t triangle_count() const;
  // Every geometry entry except mesh triangles counted one by one (spheres, quads, ...).
  std::size_t analytic_shape_count() const;

  friend bool operator==(const SceneDescription&, const SceneDescription&) = default;
};

// Limits that keep one job from exhausting the daemon; they apply to every input path.
// A server sets them from its configuration (server/config.hpp documents the keys).
struct SceneLimits {
  std::uint32_t max_width = 16384;
  std::uint32_t max_height = 16384;
  // Width x height: bounds the film (16 bytes a pixel for beauty, more with AOVs).
  std::size_t max_pixels = std::size_t{8192} * 8192;
  std::uint32_t max_samples_per_pixel = 65536;
  std::uint32_t max_depth = 64;
  std::uint32_t min_tile_size = 8;
  std::uint32_t max_tile_size = 1024;
  std::size_t max_triangles = 50'000'000;
  // Triangles plus every other shape (spheres, quads, patches, trimmed faces, ...).
  std::size_t max_primitives = 50'000'000;
  // Shapes of one type; the renderer's primitive references hold 27 index bits.
  std::size_t max_shapes_per_type = (std::size_t{1} << 27) - 1;
  // Control points of all patches together (each becomes at most one Bézier piece of
  // ~650 bytes) and uv points of all trimming loops together (16 bytes each).
  std::size_t max_patch_control_points = 250'000;
  std::size_t max_trim_points = 4'000'000;
  // Pixels of an environment image (12 bytes each as floats): 8192 x 4096.
  std::size_t max_environment_pixels = std::size_t{8192} * 4096;
  // Texels of all textures together before their mipmaps (which add a third): 64M texels,
  // about 1 GB as float RGB.
  std::size_t max_texture_pixels = std::size_t{64} << 20;
  std::size_t max_textures = 4096;
};

// Semantic checks shared by every loader, from the kind declarations (scene/schema/kinds.hpp):
// finite numbers, positive radii, valid material references, render settings in range.
// Returns every issue found in input order, field paths in `style` (the YAML file's or the
// protobuf request's terms), file and line left empty for the caller to add. Linear in the
// scene's size.
std::vector<struct SceneIssue> validate_scene(const SceneDescription& scene,
                                              const SceneLimits& limits = {},
                                              schema::PathStyle style = schema::PathStyle::kYaml);

}  // namespace tessera
