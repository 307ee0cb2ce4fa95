// The job cost counted from a request before conversion: the same counts as from the
// converted scene, and the verdicts SubmitJob answers with.
#include "server/job_cost.hpp"

#include <gtest/gtest.h>

#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera::server {
namespace {

void expect_same_size(const SceneSize& a, const SceneSize& b) {
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.vertex_attributes, b.vertex_attributes);
  EXPECT_EQ(a.shapes, b.shapes);
  EXPECT_EQ(a.patch_control_points, b.patch_control_points);
  EXPECT_EQ(a.trim_points, b.trim_points);
  EXPECT_EQ(a.environment_pixels, b.environment_pixels);
  EXPECT_EQ(a.texture_pixels, b.texture_pixels);
  EXPECT_EQ(a.materials, b.materials);
  EXPECT_EQ(a.lights, b.lights);
}

TEST(JobCost, TheRequestCountsMatchTheConvertedScene) {
  for (const char* name : {"cornell.yaml", "shapes.yaml", "patches.yaml", "textures.yaml"}) {
    SCOPED_TRACE(name);
    const SceneDescription scene =
        load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/" + name).scene;
    const v1::Scene proto = scene_to_proto(scene);
    const SceneSize from_proto = scene_size_of_proto(proto);
    expect_same_size(from_proto, scene_size(scene));
    const SceneConversion back = scene_from_proto(proto, settings_to_proto(scene.render));
    ASSERT_TRUE(back.ok()) << describe_issues(back.issues);
    expect_same_size(from_proto, scene_size(*back.scene));
  }
  // The textures example's one image (256 x 256) is counted, and costs its pyramid.
  const SceneDescription textured =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/textures.yaml").scene;
  EXPECT_EQ(scene_size(textured).texture_pixels, 256u * 256u);
  SceneSize without = scene_size(textured);
  without.texture_pixels = 0;
  EXPECT_GT(estimate_memory(scene_size(textured), textured.render).images,
            estimate_memory(without, textured.render).images + 256u * 256u * 12u);
}

v1::SubmitJobRequest identical_triangles(std::size_t count) {
  const SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  v1::SubmitJobRequest request = make_submit_request(scene, "many", 0);
  v1::TriangleMesh& mesh = *request.mutable_scene()->add_geometry()->mutable_mesh();
  for (int i = 0; i < 9; ++i) mesh.add_positions(i);
  for (std::size_t i = 0; i < count * 3; ++i) mesh.add_indices(static_cast<std::uint32_t>(i % 3));
  return request;
}

TEST(JobCost, ARequestOverTheBudgetIsRefusedNamingEstimateAndBudget) {
  const v1::SubmitJobRequest request = identical_triangles(1'000'000);
  const JobCostCheck fits = check_job_cost(request, SceneLimits{}, std::size_t{8} << 30, 2);
  EXPECT_EQ(fits.verdict, JobCostCheck::Verdict::kFits) << fits.message;
  EXPECT_GT(fits.estimate.total(), std::size_t{300} << 20);  // ~450 bytes a triangle
  EXPECT_LT(fits.estimate.total(), std::size_t{1} << 30);
  const JobCostCheck over = check_job_cost(request, SceneLimits{}, std::size_t{100} << 20, 2);
  EXPECT_EQ(over.verdict, JobCostCheck::Verdict::kOverMemoryBudget);
  EXPECT_NE(over.message.find("estimated"), std::string::npos) << over.message;
  EXPECT_NE(over.message.find("memory budget of 100 MiB"), std::string::npos) << over.message;
  // No budget: anything fits.
  EXPECT_EQ(check_job_cost(request, SceneLimits{}, 0, 2).verdict, JobCostCheck::Verdict::kFits);
}

TEST(JobCost, ARequestOverThePrimitiveLimitIsRefusedBeforeConversion) {
  SceneLimits limits;
  limits.max_primitives = 1000;
  const JobCostCheck check = check_job_cost(identical_triangles(1000), limits, 0, 1);
  EXPECT_EQ(check.verdict, JobCostCheck::Verdict::kTooManyPrimitives);
  EXPECT_NE(check.message.find("geometry: scene has 1008 primitives"), std::string::npos)
      << check.message;
}

TEST(JobCost, TilesInFlightGrowWithThreadsAndAovsButNotWithTheImage) {
  RenderSettings settings;
  settings.tile_size = 64;
  const SceneSize empty;
  const MemoryEstimate one = estimate_memory(empty, settings, {1, false});
  const MemoryEstimate eight = estimate_memory(empty, settings, {8, false});
  EXPECT_EQ(eight.tiles, 8 * one.tiles);
  settings.width = settings.height = 8192;
  EXPECT_EQ(estimate_memory(empty, settings, {1, false}).total(), one.total());
  EXPECT_EQ(estimate_memory(empty, settings, {1, true}).film, std::size_t{8192} * 8192 * 16);
  settings.aovs = kAllAovs;
  EXPECT_GT(estimate_memory(empty, settings, {1, false}).tiles, one.tiles);
}

TEST(JobCost, HugeCountsSaturateInsteadOfWrapping) {
  SceneSize size;
  size.triangles = static_cast<std::size_t>(-1) / 4;
  size.environment_pixels = static_cast<std::size_t>(-1) / 2;
  const MemoryEstimate estimate = estimate_memory(size, RenderSettings{}, {1, false});
  EXPECT_GT(estimate.accel, std::size_t{1} << 60);
  EXPECT_GT(estimate.images, std::size_t{1} << 60);
  EXPECT_EQ(estimate.total(), static_cast<std::size_t>(-1));
}

TEST(JobCost, BytesAreWrittenForPeople) {
  EXPECT_EQ(format_bytes(12), "12 B");
  EXPECT_EQ(format_bytes(std::size_t{512} << 20), "512 MiB");
  EXPECT_EQ(format_bytes(std::size_t{3} << 29), "1.5 GiB");
}

}  // namespace
}  // namespace tessera::server
