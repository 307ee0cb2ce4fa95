// Tile retries: a tile whose attempt throws is handed out again up to tile_retries times,
// then its job fails naming the tile. Failures are injected through the scheduler's
// on_tile_started hook, so the render path itself is untouched.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>

#include "server/job_id.hpp"
#include "server/scheduler.hpp"
#include "server/sqlite_job_store.hpp"
#include "tessera/image/exr.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::tiny_description;

class TileRetryTest : public ::testing::Test {
 protected:
  std::shared_ptr<Job> make_job(const std::string& name, const SceneDescription& scene) {
    static JobIdGenerator ids(7);
    const auto& r = scene.render;
    JobRecord record;
    record.id = ids.next();
    record.name = name;
    record.settings = r;
    record.tiles_total =
        static_cast<std::uint32_t>(make_tiles(r.width, r.height, r.tile_size).size());
    record.submitted_unix_ms = unix_millis_now();
    return std::make_shared<Job>(store_, store_.create_job(record, {}));
  }

  // Attempts per tile index, counted by the hook; `fails(index, attempt)` says whether the
  // attempt (1-based) throws.
  SchedulerOptions options(std::uint32_t retries, std::function<bool(std::uint32_t, int)> fails) {
    SchedulerOptions o;
    o.threads = 2;
    o.tile_retries = retries;
    o.on_tile_started = [this, fails](const Job&, const TileRect& rect) {
      int attempt = 0;
      {
        std::lock_guard lock(mutex_);
        attempt = ++attempts_[rect.index];
      }
      if (fails(rect.index, attempt)) throw std::runtime_error("injected fault");
    };
    return o;
  }

  int attempts(std::uint32_t index) {
    std::lock_guard lock(mutex_);
    return attempts_[index];
  }

  SqliteJobStore store_{":memory:"};
  std::mutex mutex_;
  std::map<std::uint32_t, int> attempts_;
};

TEST_F(TileRetryTest, ATileFailingOnceSucceedsOnItsRetry) {
  const SceneDescription scene = tiny_description(32, 32, 8);  // 16 tiles
  // The reference: the same job with no failures.
  auto reference = make_job("reference", scene);
  {
    Scheduler scheduler(options(2, [](std::uint32_t, int) { return false; }));
    scheduler.submit(reference, scene);
    scheduler.start();
    scheduler.wait_idle();
  }
  attempts_.clear();
  auto job = make_job("flaky", scene);
  Scheduler scheduler(
      options(2, [](std::uint32_t index, int attempt) { return index == 5 && attempt == 1; }));
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();

  EXPECT_EQ(job->state(), JobState::kCompleted) << job->info().error;
  EXPECT_EQ(attempts(5), 2);
  EXPECT_EQ(attempts(4), 1);
  for (std::uint32_t i = 0; i < 16; ++i) EXPECT_EQ(store_.tile_commit_count(job->id(), i), 1u);
  // The retried tile has the pixels an undisturbed run renders (the EXR bytes differ: the
  // header holds the time it was written).
  const auto pixels_of = [&](const std::string& id, std::uint32_t index) {
    for (const StoredTile& tile : store_.tiles_after(id, 0, 100))
      if (tile.index == index) return decode_exr(tile.exr).pixels;
    return std::vector<float>{};
  };
  const std::vector<float> retried = pixels_of(job->id(), 5);
  const std::vector<float> undisturbed = pixels_of(reference->id(), 5);
  ASSERT_FALSE(retried.empty());
  ASSERT_EQ(retried.size(), undisturbed.size());
  EXPECT_EQ(std::memcmp(retried.data(), undisturbed.data(), retried.size() * sizeof(float)), 0);
}

TEST_F(TileRetryTest, ATileFailingEveryTimeFailsTheJobAfterRetriesPlusOneAttempts) {
  const SceneDescription scene = tiny_description(32, 32, 8);  // 16 tiles
  auto job = make_job("doomed", scene);
  Scheduler scheduler(options(2, [](std::uint32_t index, int) { return index == 9; }));
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();

  const JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kFailed);
  EXPECT_EQ(attempts(9), 3);
  EXPECT_NE(info.error.find("tile 9 "), std::string::npos) << info.error;
  EXPECT_NE(info.error.find("3 times"), std::string::npos) << info.error;
  EXPECT_NE(info.error.find("injected fault"), std::string::npos) << info.error;
}

TEST_F(TileRetryTest, NoRetriesFailsAtTheFirstFailure) {
  const SceneDescription scene = tiny_description(16, 16, 8);  // 4 tiles
  auto job = make_job("strict", scene);
  Scheduler scheduler(options(0, [](std::uint32_t index, int) { return index == 2; }));
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();
  EXPECT_EQ(job->state(), JobState::kFailed);
  EXPECT_EQ(attempts(2), 1);
}

// A failed job retried (RetryJob) starts its tiles' failure counts afresh and renders only
// the tiles it lacks.
TEST_F(TileRetryTest, ARetriedJobRendersOnlyItsMissingTiles) {
  const SceneDescription scene = tiny_description(32, 32, 8);  // 16 tiles
  auto job = make_job("second-chance", scene);
  std::atomic<bool> broken{true};
  SchedulerOptions o = options(1, [&](std::uint32_t index, int) { return broken && index == 3; });
  o.threads = 1;
  o.load_scene = [&](const Job&) { return scene; };
  Scheduler scheduler(o);
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();
  ASSERT_EQ(job->state(), JobState::kFailed);
  EXPECT_EQ(attempts(3), 2);
  const std::uint32_t kept = job->record().tiles_done;
  EXPECT_GT(kept, 0u);

  broken = false;
  EXPECT_EQ(job->retry(), ControlResult::kDone);
  EXPECT_EQ(job->state(), JobState::kQueued);
  EXPECT_EQ(job->info().error, "");
  ASSERT_TRUE(scheduler.requeue(job));
  scheduler.wait_idle();
  EXPECT_EQ(job->state(), JobState::kCompleted) << job->info().error;
  for (std::uint32_t i = 0; i < 16; ++i)
    EXPECT_EQ(store_.tile_commit_count(job->id(), i), 1u) << "tile " << i;
  // Tiles stored before the retry were not attempted again.
  int attempts_total = 0;
  for (std::uint32_t i = 0; i < 16; ++i) attempts_total += attempts(i);
  EXPECT_EQ(attempts_total, 16 + 2);  // each tile once, tile 3 twice more (2 failed + 1)
  EXPECT_EQ(job->retry(), ControlResult::kRefused);  // completed jobs are not retried
}

TEST(TileFailureCount, SurvivesReopeningTheStoreAndResetsOnRetry) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("tile-failures-" + std::to_string(::getpid()) + ".sqlite3");
  std::filesystem::remove(path);
  JobRecord record;
  record.id = "job-failures";
  record.tiles_total = 4;
  {
    SqliteJobStore store(path);
    store.create_job(record, {});
    EXPECT_EQ(store.record_tile_failure(record.id, 2), 1u);
    EXPECT_EQ(store.record_tile_failure(record.id, 2), 2u);
    EXPECT_EQ(store.record_tile_failure(record.id, 1), 1u);
  }
  {
    SqliteJobStore store(path);
    EXPECT_EQ(store.record_tile_failure(record.id, 2), 3u);
    EXPECT_EQ(store.record_tile_failure("no-such-job", 2), 0u);
    ASSERT_TRUE(store.finish_job(record.id, JobState::kFailed, "tile 2 failed", 1));
    ASSERT_TRUE(store.retry_job(record.id));
    EXPECT_EQ(store.record_tile_failure(record.id, 2), 1u);
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tessera::server
