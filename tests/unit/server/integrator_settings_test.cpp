// Integrators and AOVs through the API: settings conversion both ways, rejection of values
// the enums do not define, and AOV channels in the streamed tile EXRs.
#include <gtest/gtest.h>

#include <thread>

#include "server/job_id.hpp"
#include "server/scheduler.hpp"
#include "server/sqlite_job_store.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/output_channels.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::tiny_scene;
using testing::tiny_settings;

TEST(IntegratorSettings, ConvertBothWays) {
  v1::RenderSettings in = tiny_settings();
  in.set_integrator(v1::INTEGRATOR_TRANSPARENCY);
  RenderSettings core = settings_from_proto(in);
  EXPECT_EQ(core.integrator, IntegratorKind::kTransparency);
  EXPECT_EQ(settings_to_proto(core).integrator(), v1::INTEGRATOR_TRANSPARENCY);

  in.set_integrator(v1::INTEGRATOR_UNSPECIFIED);
  in.add_aovs(v1::AOV_DEPTH);
  in.add_aovs(v1::AOV_ALBEDO);
  core = settings_from_proto(in);
  EXPECT_EQ(core.integrator, IntegratorKind::kPath);
  EXPECT_EQ(core.aovs, kAovDepth | kAovAlbedo);
  const v1::RenderSettings back = settings_to_proto(core);
  EXPECT_EQ(back.integrator(), v1::INTEGRATOR_PATH);
  ASSERT_EQ(back.aovs_size(), 2);
  EXPECT_EQ(back.aovs(0), v1::AOV_ALBEDO);
  EXPECT_EQ(back.aovs(1), v1::AOV_DEPTH);
}

TEST(IntegratorSettings, UnknownValuesAndMisuseAreRejectedWithTheField) {
  v1::RenderSettings settings = tiny_settings();
  settings.set_integrator(static_cast<v1::Integrator>(42));
  SceneConversion result = scene_from_proto(tiny_scene(), settings);
  ASSERT_FALSE(result.scene);
  EXPECT_EQ(result.issues.at(0).field, "settings.integrator");

  settings = tiny_settings();
  settings.add_aovs(v1::AOV_UNSPECIFIED);
  result = scene_from_proto(tiny_scene(), settings);
  ASSERT_FALSE(result.scene);
  EXPECT_EQ(result.issues.at(0).field, "settings.aovs[0]");

  settings = tiny_settings();
  settings.set_integrator(v1::INTEGRATOR_NORMALS);
  settings.add_aovs(v1::AOV_NORMAL);
  result = scene_from_proto(tiny_scene(), settings);
  ASSERT_FALSE(result.scene);
  EXPECT_EQ(result.issues.at(0).field, "settings.aovs");
}

TEST(IntegratorSettings, AovJobTilesCarryTheAovChannels) {
  v1::RenderSettings settings = tiny_settings(16, 16, 8);
  settings.add_aovs(v1::AOV_DEPTH);
  settings.add_aovs(v1::AOV_PRIMITIVE_ID);
  SceneConversion conversion = scene_from_proto(tiny_scene(), settings);
  ASSERT_TRUE(conversion.scene);
  const SceneDescription scene = *conversion.scene;

  SchedulerOptions options;
  options.threads = 1;
  Scheduler scheduler(options);
  static JobIdGenerator ids(7);
  static SqliteJobStore store(":memory:");
  JobRecord record;
  record.id = ids.next();
  record.name = "aovs";
  record.settings = scene.render;
  record.tiles_total = 4;
  auto job = std::make_shared<Job>(store, store.create_job(record, {}));
  ASSERT_TRUE(scheduler.submit(job, scene));
  scheduler.start();
  scheduler.wait_idle();
  ASSERT_EQ(job->state(), JobState::kCompleted);

  const auto prepared = PreparedScene::build(scene);
  const std::vector<StoredTile> tiles = job->tiles_after(0, 10);
  ASSERT_EQ(tiles.size(), 4u);
  for (const StoredTile& tile : tiles) {
    const ChannelImage decoded = select_channels(decode_exr_channels(tile.exr),
                                                 output_channels(kAovDepth | kAovPrimitiveId));
    TilePasses passes;
    prepared->render_tile(make_tiles(16, 16, 8).at(tile.index), passes);
    EXPECT_EQ(decoded.pixels, interleave_passes(passes, kAovDepth | kAovPrimitiveId));
  }
}

}  // namespace
}  // namespace tessera::server
