#include "tessera/render/memory_estimate.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <utility>

#include "tessera/render/output_channels.hpp"

namespace tessera {
namespace {

// Bytes per item, from the structures' sizes and calibrated against tesserad's measured
// peak RSS (README, "Budgets"). Rounded up: refusing a job that would just have fitted
// is cheaper than a daemon killed for memory.
//
// Description: a vertex is 24 bytes (double x, y, z), 48 more with normals and uvs; a
// triangle is three 4-byte indices.
constexpr std::size_t kDescriptionVertex = 24;
constexpr std::size_t kDescriptionVertexAttributes = 40;
constexpr std::size_t kDescriptionTriangle = 12;
// Render-ready triangle in float (vertices, edges) and its tagged reference; its per-vertex
// attributes when a mesh has normals or uvs.
constexpr std::size_t kTriangle = 64;
constexpr std::size_t kTriangleAttributes = 96;
// Triangle structure and BVH, counting their build's temporaries (boxes, centroids,
// references of every primitive, held at once), which set the peak. Measured: 2M scattered
// triangles peak at ~385 bytes each beyond their description (50M copies of one triangle
// took ~235 each before repeats were stored once; the estimate cannot see repeats and
// counts every triangle).
constexpr std::size_t kTriangleAccel = 384;
// A shape other than a triangle: its description, render form, box and BVH share.
constexpr std::size_t kShape = 512;
// Each control point becomes at most one Bézier piece (~650 bytes with its bounds).
constexpr std::size_t kPatchControlPoint = 720;
constexpr std::size_t kTrimPoint = 48;
// Environment pixel: the description's three floats, the renderer's copy and its sampling
// tables.
constexpr std::size_t kEnvironmentPixel = 36;
// Texture pixel: the description's three floats and the renderer's pyramid (a third more
// than its 12-byte level 0).
constexpr std::size_t kTexturePixel = 28;
constexpr std::size_t kMaterial = 256;
constexpr std::size_t kLight = 256;
// Any job, however small: the store's page cache, the worker's tile planes and EXR
// buffers, the build's task arenas (measured: ~6 MiB for the Cornell box).
constexpr std::size_t kJobBase = std::size_t{16} << 20;
// Compressed EXR bytes of a tile are at most about its raw size.
constexpr std::size_t kExrOverhead = 2;

std::size_t saturating_multiply(std::size_t count, std::size_t bytes) {
  if (bytes != 0 && count > static_cast<std::size_t>(-1) / bytes)
    return static_cast<std::size_t>(-1);
  return count * bytes;
}

std::size_t saturating_add(std::size_t a, std::size_t b) {
  return a > static_cast<std::size_t>(-1) - b ? static_cast<std::size_t>(-1) : a + b;
}

}  // namespace

SceneSize scene_size(const SceneDescription& scene) {
  SceneSize size;
  for (const TriangleMeshDesc& mesh : scene.meshes) {
    size.triangles += mesh.indices.size() / 3;
    size.vertices += mesh.positions.size();
    size.vertex_attributes = size.vertex_attributes || !mesh.normals.empty() || !mesh.uvs.empty();
  }
  size.shapes = scene.analytic_shape_count();
  for (const SplinePatchDesc& patch : scene.patches)
    size.patch_control_points += patch.control_points.size();
  for (const TrimmedFaceDesc& face : scene.trimmed_faces) {
    if (const auto* patch = std::get_if<SplinePatchDesc>(&face.surface))
      size.patch_control_points += patch->control_points.size();
    for (const auto& loop : face.loops) size.trim_points += loop.size();
  }
  if (scene.environment)
    size.environment_pixels =
        std::size_t{scene.environment->image_width} * scene.environment->image_height;
  for (const TextureDesc& texture : scene.textures)
    size.texture_pixels += std::size_t{texture.image_width} * texture.image_height;
  size.materials = scene.materials.size();
  size.lights = scene.lights.size();
  return size;
}

MemoryEstimate estimate_memory(const SceneSize& size, const RenderSettings& settings,
                               const EstimateOptions& options) {
  MemoryEstimate estimate;
  estimate.base = kJobBase;
  const std::size_t vertex_bytes =
      kDescriptionVertex + (size.vertex_attributes ? kDescriptionVertexAttributes : 0);
  estimate.description = saturating_add(saturating_multiply(size.vertices, vertex_bytes),
                                        saturating_multiply(size.triangles, kDescriptionTriangle));
  const std::size_t triangle_bytes = kTriangle + (size.vertex_attributes ? kTriangleAttributes : 0);
  estimate.geometry = saturating_add(
      saturating_add(saturating_multiply(size.triangles, triangle_bytes),
                     saturating_multiply(size.shapes, kShape)),
      saturating_add(saturating_multiply(size.patch_control_points, kPatchControlPoint),
                     saturating_multiply(size.trim_points, kTrimPoint)));
  estimate.geometry = saturating_add(estimate.geometry,
                                     saturating_add(saturating_multiply(size.materials, kMaterial),
                                                    saturating_multiply(size.lights, kLight)));
  estimate.accel = saturating_multiply(size.triangles, kTriangleAccel);
  estimate.images = saturating_add(saturating_multiply(size.environment_pixels, kEnvironmentPixel),
                                   saturating_multiply(size.texture_pixels, kTexturePixel));

  const std::size_t channels = output_channels(settings.aovs).size();
  const std::size_t pixel_bytes = channels * sizeof(float);
  if (options.whole_image)
    estimate.film = saturating_multiply(
        saturating_multiply(std::size_t{settings.width}, settings.height), pixel_bytes);
  // A tile's planes while it renders and its EXR bytes until they are stored, per thread.
  const std::size_t tile_pixels = std::size_t{settings.tile_size} * settings.tile_size;
  estimate.tiles =
      saturating_multiply(saturating_multiply(tile_pixels, pixel_bytes * (1 + kExrOverhead)),
                          std::max(1u, options.threads));
  return estimate;
}

std::string format_bytes(std::size_t bytes) {
  static constexpr std::array<const char*, 5> kUnits = {"B", "KiB", "MiB", "GiB", "TiB"};
  double value = static_cast<double>(bytes);
  std::size_t unit = 0;
  while (value >= 1024.0 && unit + 1 < kUnits.size()) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  if (unit == 0 || value >= 100.0)
    std::snprintf(text, sizeof text, "%.0f %s", value, kUnits[unit]);
  else
    std::snprintf(text, sizeof text, "%.1f %s", value, kUnits[unit]);
  return text;
}

std::size_t MemoryEstimate::total() const {
  std::size_t sum = 0;
  for (const std::size_t part : {base, description, geometry, accel, images, film, tiles})
    sum = saturating_add(sum, part);
  return sum;
}

std::string MemoryEstimate::describe() const {
  std::array<std::pair<const char*, std::size_t>, 7> parts = {{{"scene description", description},
                                                               {"per job", base},
                                                               {"geometry", geometry},
                                                               {"BVH", accel},
                                                               {"images", images},
                                                               {"film", film},
                                                               {"tiles in flight", tiles}}};
  std::stable_sort(parts.begin(), parts.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text = format_bytes(total()) + " (";
  bool first = true;
  for (const auto& [name, bytes] : parts) {
    if (bytes == 0) continue;
    if (!first) text += ", ";
    first = false;
    text.append(name).append(" ").append(format_bytes(bytes));
  }
  return text + ")";
}

}  // namespace tessera
