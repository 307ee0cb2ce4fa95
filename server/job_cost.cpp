#include "server/job_cost.hpp"

#include <unistd.h>

#include <algorithm>

#include "convert/scene_proto.hpp"

namespace tessera::server {

SceneSize scene_size_of_proto(const v1::Scene& scene) {
  SceneSize size;
  for (const v1::Geometry& geometry : scene.geometry()) {
    switch (geometry.shape_case()) {
      case v1::Geometry::kTriangle:
        size.triangles += 1;
        size.vertices += 3;
        break;
      case v1::Geometry::kMesh: {
        const v1::TriangleMesh& mesh = geometry.mesh();
        size.triangles += static_cast<std::size_t>(mesh.indices_size()) / 3;
        size.vertices += static_cast<std::size_t>(mesh.positions_size()) / 3;
        size.vertex_attributes =
            size.vertex_attributes || mesh.normals_size() > 0 || mesh.uvs_size() > 0;
        break;
      }
      case v1::Geometry::kSplinePatch:
        size.shapes += 1;
        size.patch_control_points +=
            static_cast<std::size_t>(geometry.spline_patch().control_points_size()) / 3;
        break;
      case v1::Geometry::kTrimmedFace: {
        const v1::TrimmedFace& face = geometry.trimmed_face();
        size.shapes += 1;
        if (face.has_patch())
          size.patch_control_points +=
              static_cast<std::size_t>(face.patch().control_points_size()) / 3;
        for (const v1::UvLoop& loop : face.loops())
          size.trim_points += static_cast<std::size_t>(loop.uv_size()) / 2;
        break;
      }
      default:
        size.shapes += 1;
        break;
    }
  }
  if (scene.has_environment()) {
    const v1::Environment& environment = scene.environment();
    size.environment_pixels =
        std::max(std::size_t{environment.image_width()} * environment.image_height(),
                 static_cast<std::size_t>(environment.image_pixels_size()) / 3);
  }
  for (const v1::Texture& texture : scene.textures())
    size.texture_pixels +=
        std::max(std::size_t{texture.image_width()} * texture.image_height(),
                 static_cast<std::size_t>(texture.image_pixels_size()) / 3);
  size.materials = static_cast<std::size_t>(scene.materials_size());
  size.lights = static_cast<std::size_t>(scene.lights_size());
  return size;
}

JobCostCheck check_job_cost(const v1::SubmitJobRequest& request, const SceneLimits& limits,
                            std::size_t memory_budget, unsigned threads) {
  JobCostCheck check;
  const SceneSize size = scene_size_of_proto(request.scene());
  const std::size_t primitives = size.triangles + size.shapes;
  if (primitives > limits.max_primitives) {
    check.verdict = JobCostCheck::Verdict::kTooManyPrimitives;
    check.message = "geometry: scene has " + std::to_string(primitives) +
                    " primitives (triangles and other shapes), more than the limit of " +
                    std::to_string(limits.max_primitives);
    return check;
  }
  RenderSettings settings = settings_from_proto(request.settings());
  // Out-of-range sizes are the scene checks' to report; the estimate takes them in range.
  settings.tile_size = std::clamp(settings.tile_size, limits.min_tile_size, limits.max_tile_size);
  check.estimate = estimate_memory(size, settings, EstimateOptions{threads, false});
  if (memory_budget != 0 && check.estimate.total() > memory_budget) {
    check.verdict = JobCostCheck::Verdict::kOverMemoryBudget;
    check.message = "the job needs an estimated " + check.estimate.describe() +
                    ", more than the daemon's memory budget of " + format_bytes(memory_budget) +
                    " (memory_budget in the configuration)";
  }
  return check;
}

std::size_t default_memory_budget() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::size_t{8} << 30;  // unknown: a modest node
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size) / 2;
}

}  // namespace tessera::server
