#include "server/scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>

#include "server/job_id.hpp"
#include "tessera/image/exr.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::tiny_description;

std::shared_ptr<Job> make_job(const std::string& name, int priority,
                              const SceneDescription& scene) {
  static JobIdGenerator ids(1);
  const auto& r = scene.render;
  const auto tiles = static_cast<std::uint32_t>(make_tiles(r.width, r.height, r.tile_size).size());
  return std::make_shared<Job>(ids.next(), name, priority, r, tiles, unix_millis_now());
}

// Collects every tile of a job the way StreamTiles does; returns the tile indices in the
// order received.
std::vector<std::uint32_t> subscribe(const Job& job, std::vector<FinishedTile>* tiles = nullptr) {
  std::vector<std::uint32_t> indices;
  for (;;) {
    const TileUpdate update = job.wait_for_tiles(indices.size(), 50ms);
    for (const FinishedTile& tile : update.tiles) {
      indices.push_back(tile.rect.index);
      if (tiles) tiles->push_back(tile);
    }
    if (update.finished) return indices;
  }
}

TEST(Scheduler, StartsJobsByPriorityThenSubmissionOrder) {
  std::mutex mutex;
  std::vector<std::string> started;
  SchedulerOptions options;
  options.threads = 1;
  options.on_job_started = [&](const Job& job) {
    std::lock_guard lock(mutex);
    started.push_back(job.name());
  };
  Scheduler scheduler(options);
  const SceneDescription scene = tiny_description();
  std::vector<std::shared_ptr<Job>> jobs = {make_job("low", 0, scene), make_job("high-1", 5, scene),
                                            make_job("high-2", 5, scene), make_job("mid", 2, scene),
                                            make_job("negative", -3, scene)};
  for (const auto& job : jobs) ASSERT_TRUE(scheduler.submit(job, scene));
  scheduler.start();
  scheduler.wait_idle();

  EXPECT_EQ(started, (std::vector<std::string>{"high-1", "high-2", "mid", "low", "negative"}));
  for (const auto& job : jobs) {
    const JobInfo info = job->info();
    EXPECT_EQ(info.state, JobState::kCompleted) << info.name;
    EXPECT_EQ(info.progress.tiles_done, 4u);
    EXPECT_EQ(info.progress.tiles_total, 4u);
    EXPECT_GT(info.progress.rays_traced, 0u);
    EXPECT_GT(info.finished_unix_ms, 0);
  }
}

TEST(Scheduler, ALaterHigherPriorityJobTakesTheNextTiles) {
  // One worker: after the low job's first tile, a high-priority job arrives; every one of
  // its tiles must be rendered before the low job's remaining ones.
  const SceneDescription big = tiny_description(32, 32, 8);    // 16 tiles
  const SceneDescription small = tiny_description(16, 16, 8);  // 4 tiles
  std::mutex mutex;
  std::vector<std::string> rendered;
  std::shared_ptr<Job> high = make_job("high", 10, small);
  Scheduler* scheduler_ptr = nullptr;
  SchedulerOptions options;
  options.threads = 1;
  options.on_tile_rendered = [&](const Job& job, const TileRect&, bool) {
    std::lock_guard lock(mutex);
    rendered.push_back(job.name());
    if (rendered.size() == 1) scheduler_ptr->submit(high, small);
  };
  Scheduler scheduler(options);
  scheduler_ptr = &scheduler;
  std::shared_ptr<Job> low = make_job("low", 0, big);
  scheduler.submit(low, big);
  scheduler.start();
  scheduler.wait_idle();

  std::vector<std::string> expected = {"low", "high", "high", "high", "high"};
  expected.resize(4 + 16, "low");
  EXPECT_EQ(rendered, expected);
  EXPECT_EQ(low->state(), JobState::kCompleted);
  EXPECT_EQ(high->state(), JobState::kCompleted);
}

TEST(Scheduler, CancellationStopsTheRemainingTiles) {
  const SceneDescription scene = tiny_description(64, 64, 8);  // 64 tiles
  std::shared_ptr<Job> job = make_job("cancel-me", 0, scene);
  std::atomic<int> rendered{0};
  Scheduler* scheduler_ptr = nullptr;
  SchedulerOptions options;
  options.threads = 1;
  options.on_tile_rendered = [&](const Job& j, const TileRect&, bool) {
    if (++rendered == 3) {
      EXPECT_EQ(const_cast<Job&>(j).cancel("test"), CancelResult::kCancelled);
      scheduler_ptr->job_changed();
    }
  };
  Scheduler scheduler(options);
  scheduler_ptr = &scheduler;
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();

  EXPECT_EQ(rendered.load(), 3);
  const JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kCancelled);
  EXPECT_EQ(info.cancel_reason, "test");
  EXPECT_EQ(info.progress.tiles_done, 3u);
  EXPECT_EQ(info.progress.tiles_total, 64u);
}

TEST(Scheduler, TilesInFlightWhenCancelledAreDropped) {
  const SceneDescription scene = tiny_description(64, 64, 8);
  std::shared_ptr<Job> job = make_job("cancel-me", 0, scene);
  std::atomic<int> rendered{0};
  std::atomic<int> kept{0};
  std::atomic<std::uint32_t> stored_at_cancel{0};
  Scheduler* scheduler_ptr = nullptr;
  SchedulerOptions options;
  options.threads = 2;
  options.on_tile_rendered = [&](const Job& j, const TileRect&, bool was_kept) {
    kept += was_kept ? 1 : 0;
    if (++rendered == 2) {
      const_cast<Job&>(j).cancel("test");
      stored_at_cancel = j.info().progress.tiles_done;
      scheduler_ptr->job_changed();
    }
  };
  Scheduler scheduler(options);
  scheduler_ptr = &scheduler;
  scheduler.submit(job, scene);
  scheduler.start();
  scheduler.wait_idle();

  // At most one tile per other worker can be in flight when the job is cancelled, and
  // none of them is stored.
  EXPECT_LE(rendered.load(), 2 + 1);
  EXPECT_EQ(job->info().progress.tiles_done, stored_at_cancel.load());
  EXPECT_EQ(static_cast<std::uint32_t>(kept.load()), stored_at_cancel.load());
  EXPECT_EQ(job->state(), JobState::kCancelled);
}

TEST(Scheduler, AJobCancelledWhileQueuedIsNeverPrepared) {
  std::atomic<int> prepared{0};
  SchedulerOptions options;
  options.threads = 1;
  options.prepare = [&](const SceneDescription& scene) {
    ++prepared;
    return default_prepare(scene);
  };
  Scheduler scheduler(options);
  const SceneDescription scene = tiny_description();
  auto cancelled = make_job("cancelled", 0, scene);
  auto kept = make_job("kept", 0, scene);
  scheduler.submit(cancelled, scene);
  scheduler.submit(kept, scene);
  EXPECT_EQ(cancelled->cancel(), CancelResult::kCancelled);
  scheduler.job_changed();
  scheduler.start();
  scheduler.wait_idle();
  EXPECT_EQ(prepared.load(), 1);
  EXPECT_EQ(cancelled->info().progress.tiles_done, 0u);
  EXPECT_EQ(kept->state(), JobState::kCompleted);
}

TEST(Scheduler, AFailingJobDoesNotAffectTheOthers) {
  SchedulerOptions options;
  options.threads = 2;
  options.prepare = [](const SceneDescription& scene) -> std::shared_ptr<const PreparedScene> {
    if (scene.render.width == 24) throw std::runtime_error("out of unobtainium");
    return default_prepare(scene);
  };
  Scheduler scheduler(options);
  const SceneDescription good = tiny_description(16, 16, 8);
  const SceneDescription bad = tiny_description(24, 16, 8);
  auto before = make_job("before", 0, good);
  auto failing = make_job("failing", 5, bad);
  auto after = make_job("after", 0, good);
  scheduler.submit(before, good);
  scheduler.submit(failing, bad);
  scheduler.start();
  std::vector<FinishedTile> tiles;
  EXPECT_TRUE(subscribe(*failing, &tiles).empty());
  scheduler.submit(after, good);
  scheduler.wait_idle();

  const JobInfo info = failing->info();
  EXPECT_EQ(info.state, JobState::kFailed);
  EXPECT_EQ(info.error, "scene preparation failed: out of unobtainium");
  EXPECT_GT(info.finished_unix_ms, 0);
  EXPECT_EQ(before->state(), JobState::kCompleted);
  EXPECT_EQ(after->state(), JobState::kCompleted);
  EXPECT_EQ(after->info().progress.tiles_done, 4u);
}

TEST(Scheduler, EveryTileReachesEachSubscriberExactlyOnce) {
  const SceneDescription scene = tiny_description(32, 24, 8);  // 4 x 3 tiles
  auto job = make_job("watched", 0, scene);
  SchedulerOptions options;
  options.threads = 2;
  Scheduler scheduler(options);
  scheduler.submit(job, scene);

  std::vector<std::uint32_t> early, late, after_the_end;
  std::vector<FinishedTile> early_tiles;
  std::thread early_subscriber([&] { early = subscribe(*job, &early_tiles); });
  scheduler.start();
  // The late subscriber joins once some tiles are done, so it gets the backlog first.
  while (job->info().progress.tiles_done < 3 && !job->finished()) std::this_thread::sleep_for(1ms);
  std::thread late_subscriber([&] { late = subscribe(*job); });
  early_subscriber.join();
  late_subscriber.join();
  after_the_end = subscribe(*job);
  scheduler.wait_idle();

  std::vector<std::uint32_t> all(12);
  std::iota(all.begin(), all.end(), 0u);
  for (auto* received : {&early, &late, &after_the_end}) {
    ASSERT_EQ(received->size(), 12u);
    std::vector<std::uint32_t> sorted = *received;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, all);
  }
  EXPECT_EQ(early, late);  // the same order: the job's storage order
  EXPECT_EQ(job->state(), JobState::kCompleted);

  // Each tile's EXR holds exactly what rendering that rectangle directly gives.
  const auto prepared = PreparedScene::build(scene);
  for (const FinishedTile& tile : early_tiles) {
    const RgbaImage decoded = decode_exr(*tile.exr);
    ASSERT_EQ(decoded.width, tile.rect.width);
    ASSERT_EQ(decoded.height, tile.rect.height);
    std::vector<float> expected(tile.rect.pixel_count() * 4);
    prepared->render_tile(tile.rect, expected);
    EXPECT_EQ(decoded.pixels, expected) << "tile " << tile.rect.index;
  }
  // Progress counts up one tile at a time, and the last tile reports the job done.
  std::set<std::uint32_t> done_counts;
  for (const FinishedTile& tile : early_tiles) done_counts.insert(tile.progress.tiles_done);
  EXPECT_EQ(done_counts.size(), 12u);
  EXPECT_EQ(early_tiles.back().progress.tiles_done, 12u);
  EXPECT_EQ(early_tiles.back().progress.eta_seconds, 0.0);
}

TEST(Scheduler, StopCancelsUnfinishedJobsAndRejectsNewOnes) {
  SchedulerOptions options;
  options.threads = 1;
  Scheduler scheduler(options);
  const SceneDescription scene = tiny_description();
  auto queued = make_job("queued", 0, scene);
  scheduler.submit(queued, scene);  // never started: no workers yet
  scheduler.stop("daemon shutting down");
  EXPECT_EQ(queued->state(), JobState::kCancelled);
  EXPECT_EQ(queued->info().cancel_reason, "daemon shutting down");
  EXPECT_FALSE(scheduler.submit(make_job("late", 0, scene), scene));
  scheduler.stop("again");  // idempotent
}

TEST(Scheduler, RejectsAJobWhoseTileCountDoesNotMatchItsScene) {
  Scheduler scheduler(SchedulerOptions{});
  const SceneDescription scene = tiny_description(16, 16, 8);
  auto job = std::make_shared<Job>("job-x", "x", 0, scene.render, 5, 0);
  EXPECT_THROW(scheduler.submit(job, scene), std::logic_error);
}

}  // namespace
}  // namespace tessera::server
