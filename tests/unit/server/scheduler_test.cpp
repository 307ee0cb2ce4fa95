#include "server/scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <future>
#include <iostream>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>

#include "server/job_id.hpp"
#include "server/job_passes.hpp"
#include "server/metrics.hpp"
#include "server/sqlite_job_store.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/output_channels.hpp"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::tiny_description;

// Every job of these tests lives in one in-memory store, as the daemon's would.
JobStore& test_store() {
  static SqliteJobStore store(":memory:");
  return store;
}

JobRecord make_record(const std::string& name, int priority, const SceneDescription& scene,
                      const std::string& submitter = "") {
  static JobIdGenerator ids(1);
  const auto& r = scene.render;
  JobRecord record;
  record.id = ids.next();
  record.name = name;
  record.submitter = submitter;
  record.priority = priority;
  record.settings = r;
  record.tiles_total = static_cast<std::uint32_t>(PassLayout(r).units());  // tiles x passes
  record.submitted_unix_ms = unix_millis_now();
  return record;
}

std::shared_ptr<Job> make_job(const std::string& name, int priority, const SceneDescription& scene,
                              const std::string& submitter = "") {
  return std::make_shared<Job>(
      test_store(), test_store().create_job(make_record(name, priority, scene, submitter), {}));
}

// Collects every tile of a job the way StreamTiles does; returns the tile indices in the
// order received.
std::vector<std::uint32_t> subscribe(const Job& job, std::vector<StoredTile>* tiles = nullptr) {
  std::vector<std::uint32_t> indices;
  for (;;) {
    const TileUpdate update = job.wait_for_tiles(indices.size(), 50ms);
    for (StoredTile& tile : job.tiles_after(static_cast<std::uint32_t>(indices.size()), 1000)) {
      indices.push_back(tile.index);
      if (tiles) tiles->push_back(std::move(tile));
    }
    if (update.finished && indices.size() >= update.tiles_done) return indices;
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
  std::atomic<int> rendered_at_cancel{0};
  Scheduler* scheduler_ptr = nullptr;
  SchedulerOptions options;
  options.threads = 2;
  options.on_tile_rendered = [&](const Job& j, const TileRect&, bool was_kept) {
    kept += was_kept ? 1 : 0;
    if (++rendered == 2) {
      const_cast<Job&>(j).cancel("test");
      // Counted once the cancel has happened: the other worker may have finished a tile
      // and claimed the next between the count above and the cancel.
      rendered_at_cancel = rendered.load();
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
  EXPECT_LE(rendered.load(), rendered_at_cancel.load() + 1);
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
  std::vector<StoredTile> tiles;
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
  std::vector<StoredTile> early_tiles;
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
  const std::vector<TileRect> grid = make_tiles(32, 24, 8);
  for (const StoredTile& tile : early_tiles) {
    const TileRect& rect = grid.at(tile.index);
    const RgbaImage decoded = decode_exr(tile.exr);
    ASSERT_EQ(decoded.width, rect.width);
    ASSERT_EQ(decoded.height, rect.height);
    std::vector<float> expected(rect.pixel_count() * 4);
    prepared->render_tile(rect, expected);
    EXPECT_EQ(decoded.pixels, expected) << "tile " << tile.index;
  }
  // Progress counts up one tile at a time, and the last tile reports the job done.
  const JobRecord record = job->record();
  std::set<std::uint32_t> done_counts;
  for (const StoredTile& tile : early_tiles)
    done_counts.insert(tile_progress(record, tile).tiles_done);
  EXPECT_EQ(done_counts.size(), 12u);
  EXPECT_EQ(tile_progress(record, early_tiles.back()).tiles_done, 12u);
  EXPECT_EQ(tile_progress(record, early_tiles.back()).eta_seconds, 0.0);
}

TEST(Scheduler, StopLeavesJobsForARestartAndRejectsNewOnes) {
  SchedulerOptions options;
  options.threads = 1;
  Scheduler scheduler(options);
  const SceneDescription scene = tiny_description();
  auto queued = make_job("queued", 0, scene);
  scheduler.submit(queued, scene);  // never started: no workers yet
  scheduler.stop();
  // Not cancelled: the store still has it queued, for the next daemon to run.
  EXPECT_EQ(queued->state(), JobState::kQueued);
  EXPECT_EQ(test_store().find_job(queued->id())->state, JobState::kQueued);
  EXPECT_FALSE(scheduler.submit(make_job("late", 0, scene), scene));
  scheduler.stop();  // idempotent
}

// A job resumed after a restart: the tiles its store already holds are not rendered again,
// and the finished job holds every tile exactly once.
TEST(Scheduler, AResumedJobRendersOnlyTheTilesNotStored) {
  const SceneDescription scene = tiny_description(32, 32, 8);  // 16 tiles
  auto job = make_job("resumed", 0, scene);
  // A previous run stored tiles 0, 5 and 9 (any bytes do: they are not looked at again).
  ASSERT_TRUE(job->mark_running());
  for (const std::uint32_t index : {0u, 5u, 9u})
    ASSERT_EQ(job->add_tile(make_tiles(32, 32, 8)[index], "before", {1}, 1),
              AddTileResult::kStored);
  auto resumed = std::make_shared<Job>(test_store(), *test_store().find_job(job->id()));

  std::mutex mutex;
  std::vector<std::uint32_t> rendered;
  SchedulerOptions options;
  options.threads = 2;
  options.load_scene = [&](const Job&) { return scene; };
  options.on_tile_rendered = [&](const Job&, const TileRect& rect, bool) {
    std::lock_guard lock(mutex);
    rendered.push_back(rect.index);
  };
  Scheduler scheduler(options);
  scheduler.submit(resumed);  // scene read through load_scene, as the daemon does
  scheduler.start();
  scheduler.wait_idle();

  std::sort(rendered.begin(), rendered.end());
  std::vector<std::uint32_t> expected;
  for (std::uint32_t i = 0; i < 16; ++i)
    if (i != 0 && i != 5 && i != 9) expected.push_back(i);
  EXPECT_EQ(rendered, expected);
  EXPECT_EQ(resumed->state(), JobState::kCompleted);
  for (std::uint32_t i = 0; i < 16; ++i)
    EXPECT_EQ(test_store().tile_commit_count(job->id(), i), 1u) << "tile " << i;
}

// One tile far too big to finish (hours of work at 65,536 spp): a cancel must reach it
// while it renders, and the cut-short tile must not be stored. Without the check in the
// tile loop this test would not end.
TEST(Scheduler, CancelReachesATileBeingRendered) {
  SceneDescription scene = tiny_description(1024, 1024, 1024);
  scene.render.samples_per_pixel = 65536;
  auto job = make_job("huge", 0, scene);
  std::promise<void> started;
  std::atomic<int> kept{-1};
  SchedulerOptions options;
  options.threads = 1;
  options.on_tile_started = [&](const Job&, const TileRect&) { started.set_value(); };
  options.on_tile_rendered = [&](const Job&, const TileRect&, bool was_kept) {
    kept = was_kept ? 1 : 0;
  };
  Scheduler scheduler(options);
  scheduler.submit(job, scene);
  scheduler.start();
  started.get_future().wait();
  EXPECT_EQ(job->cancel("test"), CancelResult::kCancelled);
  scheduler.job_changed();
  scheduler.wait_idle();
  EXPECT_EQ(kept.load(), 0);
  EXPECT_EQ(job->info().progress.tiles_done, 0u);
  EXPECT_EQ(test_store().tile_commit_count(job->id(), 0), 0u);
}

// Stopping the daemon abandons a tile that outlasts the grace period: it stops, is not
// stored, and the job stays running in the store for the next start.
TEST(Scheduler, StopAbandonsATileThatOutlastsTheGracePeriod) {
  SceneDescription scene = tiny_description(1024, 1024, 1024);
  scene.render.samples_per_pixel = 65536;
  auto job = make_job("huge", 0, scene);
  std::promise<void> started;
  std::atomic<int> kept{-1};
  SchedulerOptions options;
  options.threads = 1;
  options.on_tile_started = [&](const Job&, const TileRect&) { started.set_value(); };
  options.on_tile_rendered = [&](const Job&, const TileRect&, bool was_kept) {
    kept = was_kept ? 1 : 0;
  };
  Scheduler scheduler(options);
  scheduler.submit(job, scene);
  scheduler.start();
  started.get_future().wait();
  scheduler.stop(10ms);
  EXPECT_EQ(kept.load(), 0);
  EXPECT_EQ(test_store().find_job(job->id())->state, JobState::kRunning);
  EXPECT_EQ(test_store().tile_commit_count(job->id(), 0), 0u);
}

// Records which job each rendered tile belonged to, in order (one worker: a total order).
struct RenderOrder {
  std::mutex mutex;
  std::vector<std::string> names;
  // How many tiles `name` had rendered when `other` rendered its last.
  std::size_t count_before_last(const std::string& name, const std::string& other) {
    std::lock_guard lock(mutex);
    const auto last = std::find(names.rbegin(), names.rend(), other);
    return static_cast<std::size_t>(std::count(names.begin(), last.base(), name));
  }
  std::function<void(const Job&, const TileRect&, bool)> recorder() {
    return [this](const Job& job, const TileRect&, bool) {
      std::lock_guard lock(mutex);
      names.push_back(job.name());
    };
  }
};

// Same priority, two submitters: "a" queued two big jobs first, "b" a small one after. The
// worker alternates between the submitters, so b finishes after four of a1's tiles, and
// a2 (a's second job) has not begun.
TEST(Scheduler, SubmittersOfOnePriorityShareTheWorkersRoundRobin) {
  const SceneDescription big = tiny_description(32, 32, 8);    // 16 tiles
  const SceneDescription small = tiny_description(16, 16, 8);  // 4 tiles
  RenderOrder order;
  SchedulerOptions options;
  options.threads = 1;
  options.on_tile_rendered = order.recorder();
  Scheduler scheduler(options);
  auto a1 = make_job("a1", 0, big, "a");
  auto a2 = make_job("a2", 0, big, "a");
  auto b = make_job("b", 0, small, "b");
  scheduler.submit(a1, big);
  scheduler.submit(a2, big);
  scheduler.submit(b, small);
  scheduler.start();
  scheduler.wait_idle();
  EXPECT_EQ(order.count_before_last("a1", "b"), 4u);
  EXPECT_EQ(order.count_before_last("a2", "b"), 0u);
  EXPECT_EQ(b->state(), JobState::kCompleted);
  EXPECT_EQ(a2->state(), JobState::kCompleted);
}

// A long high-priority job yields every 8th tile once it has had 32: a short low-priority
// job finishes long before it instead of after it.
TEST(Scheduler, ALongHighPriorityJobYieldsAShareToLowerOnes) {
  const SceneDescription long_scene = tiny_description(128, 128, 8);  // 256 tiles
  const SceneDescription short_scene = tiny_description(16, 16, 8);   // 4 tiles
  for (const std::uint32_t yield_every : {8u, 0u}) {
    RenderOrder order;
    SchedulerOptions options;
    options.threads = 1;
    options.yield_every = yield_every;
    options.on_tile_rendered = order.recorder();
    Scheduler scheduler(options);
    auto high = make_job("high", 10, long_scene);
    auto low = make_job("low", 0, short_scene);
    scheduler.submit(high, long_scene);
    scheduler.submit(low, short_scene);
    scheduler.start();
    scheduler.wait_idle();
    EXPECT_EQ(high->state(), JobState::kCompleted);
    EXPECT_EQ(low->state(), JobState::kCompleted);
    const std::size_t high_before_low_done = order.count_before_last("high", "low");
    std::cout << "yield_every " << yield_every << ": the 4-tile low job finished after "
              << high_before_low_done << " of the high job's 256 tiles\n";
    if (yield_every == 0) {
      EXPECT_EQ(high_before_low_done, 256u);  // strict priority: low waits for all of it
    } else {
      // 32 tiles of its own, then one hand-out in 8 to the low job: its preparation and
      // its 4 tiles take 5 of them.
      EXPECT_GE(high_before_low_done, 32u);
      EXPECT_LE(high_before_low_done, 32u + 5 * 8);
    }
  }
}

TEST(Scheduler, RejectsAJobWhoseTileCountDoesNotMatchItsScene) {
  Scheduler scheduler(SchedulerOptions{});
  const SceneDescription scene = tiny_description(16, 16, 8);
  JobRecord record = make_record("x", 0, scene);
  record.tiles_total = 5;
  auto job = std::make_shared<Job>(test_store(), test_store().create_job(record, {}));
  EXPECT_THROW(scheduler.submit(job, scene), std::logic_error);
}

// A device that renders through the scene's device layout on the CPU (what a GPU renders,
// tests/unit/render/device_layout_test.cpp), counting its tiles; or one whose every tile
// fails, or one that takes no job.
class StandInDevice : public TileDevice {
 public:
  enum class Mode { kRender, kFail, kRefuse };
  explicit StandInDevice(Mode mode, std::size_t batch_pixels = 0)
      : mode_(mode), batch_pixels_(batch_pixels) {}
  std::string name() const override { return "stand-in device"; }
  std::size_t batch_pixels() const override { return batch_pixels_; }
  std::vector<TileStats> render_tiles(const std::shared_ptr<const PreparedScene>& scene,
                                      std::span<const TileRect> tiles,
                                      std::span<TilePasses> passes) override {
    ++batches;
    batched_tiles += static_cast<int>(tiles.size());
    int largest = largest_batch.load();
    while (static_cast<int>(tiles.size()) > largest &&
           !largest_batch.compare_exchange_weak(largest, static_cast<int>(tiles.size()))) {
    }
    return TileDevice::render_tiles(scene, tiles, passes);
  }
  bool accepts(const PreparedScene& scene) const override {
    return mode_ != Mode::kRefuse && scene.device_source().unsupported.empty();
  }
  TileStats render_tile(const std::shared_ptr<const PreparedScene>& scene, const TileRect& tile,
                        TilePasses& passes) override {
    ++attempts;
    if (mode_ == Mode::kFail) throw std::runtime_error("the device fell off the bus");
    return scene->render_tile_device_layout(tile, passes);
  }
  std::atomic<int> attempts{0};
  std::atomic<int> batches{0}, batched_tiles{0}, largest_batch{0};  // render_tiles calls

 private:
  Mode mode_;
  std::size_t batch_pixels_;
};

// The job's image, tile by tile, from a scheduler with `devices` beside one CPU worker: RGBA,
// or with `every_channel` each tile's EXR channels, AOVs included.
std::vector<std::vector<float>> render_with(const SceneDescription& scene,
                                            std::vector<std::shared_ptr<TileDevice>> devices,
                                            std::uint32_t* tiles_done = nullptr,
                                            DaemonMetrics* metrics = nullptr,
                                            bool every_channel = false) {
  auto job = make_job("devices", 0, scene);
  SchedulerOptions options;
  options.threads = 1;
  options.devices = std::move(devices);
  options.metrics = metrics;
  // Slow enough per tile that the device's worker is up before the CPU worker is through.
  options.on_tile_started = [](const Job&, const TileRect&) { std::this_thread::sleep_for(2ms); };
  Scheduler scheduler(options);
  scheduler.submit(job, scene);
  scheduler.start();
  std::vector<StoredTile> tiles;
  subscribe(*job, &tiles);
  scheduler.wait_idle();
  EXPECT_EQ(job->state(), JobState::kCompleted);
  if (tiles_done) *tiles_done = job->info().progress.tiles_done;
  std::vector<std::vector<float>> images(tiles.size());
  for (const StoredTile& tile : tiles) {
    EXPECT_LT(tile.index, images.size());
    if (tile.index < images.size())
      images[tile.index] =
          every_channel ? decode_exr_channels(tile.exr).pixels : decode_exr(tile.exr).pixels;
  }
  return images;
}

TEST(SchedulerDevices, ADeviceTakesTilesFromTheSameQueueAndTheImageIsTheCpus) {
  const SceneDescription scene = tiny_description(64, 48, 8);  // 48 tiles
  const auto cpu_only = render_with(scene, {});
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kRender);
  std::uint32_t done = 0;
  DaemonMetrics metrics;
  const auto mixed = render_with(scene, {device}, &done, &metrics);
  EXPECT_EQ(done, 48u);
  EXPECT_GT(device->attempts.load(), 0);
  EXPECT_LT(device->attempts.load(), 48);  // the CPU worker took tiles too
  EXPECT_EQ(device->largest_batch.load(), 1) << "no batch_pixels: one tile per call";
  EXPECT_EQ(mixed, cpu_only);
  // The split is counted where it happened: the device's tiles, the CPU's the rest.
  EXPECT_EQ(metrics.tiles_rendered_by(1), static_cast<std::uint64_t>(device->attempts.load()));
  EXPECT_EQ(metrics.tiles_rendered_by(0) + metrics.tiles_rendered_by(1), 48u);
  EXPECT_EQ(metrics.tiles_fallen_back(0), 0u);
  const std::string exposition = metrics.exposition({});
  EXPECT_NE(exposition.find("tessera_tiles_rendered_by_device_total{device=\"stand-in device\"} " +
                            std::to_string(device->attempts.load()) + "\n"),
            std::string::npos)
      << exposition;
}

TEST(SchedulerDevices, ATileThatFailsOnTheDeviceIsRenderedOnTheCpu) {
  const SceneDescription scene = tiny_description(32, 32, 8);
  const auto cpu_only = render_with(scene, {});
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kFail);
  DaemonMetrics metrics;
  const auto mixed = render_with(scene, {device}, nullptr, &metrics);
  EXPECT_GT(device->attempts.load(), 0);
  EXPECT_EQ(mixed, cpu_only);
  EXPECT_EQ(metrics.tiles_fallen_back(0), static_cast<std::uint64_t>(device->attempts.load()));
  EXPECT_EQ(metrics.tiles_rendered_by(1), 0u);
  EXPECT_EQ(metrics.tiles_rendered_by(0), 16u);
}

TEST(SchedulerDevices, ADeviceThatRendersManyPixelsAtOnceTakesConsecutiveTilesTogether) {
  const SceneDescription scene = tiny_description(64, 48, 8);  // 48 tiles of 64 pixels
  const auto cpu_only = render_with(scene, {});
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kRender, 4 * 64 + 10);
  DaemonMetrics metrics;
  std::uint32_t done = 0;
  const auto mixed = render_with(scene, {device}, &done, &metrics);
  EXPECT_EQ(done, 48u);
  EXPECT_EQ(mixed, cpu_only);  // the batch's tiles are the job's tiles, each in its place
  EXPECT_LE(device->largest_batch.load(), 4) << "no more pixels than the device asked for";
  EXPECT_GT(device->largest_batch.load(), 1) << "several tiles per call";
  EXPECT_EQ(metrics.tiles_rendered_by(1), static_cast<std::uint64_t>(device->attempts.load()));
  EXPECT_EQ(metrics.tiles_rendered_by(0) + metrics.tiles_rendered_by(1), 48u);
}

TEST(SchedulerDevices, ABatchThatFailsOnTheDeviceIsRenderedOnTheCpu) {
  const SceneDescription scene = tiny_description(32, 32, 8);  // 16 tiles
  const auto cpu_only = render_with(scene, {});
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kFail, 4 * 64);
  DaemonMetrics metrics;
  std::uint32_t done = 0;
  const auto mixed = render_with(scene, {device}, &done, &metrics);
  EXPECT_EQ(done, 16u);
  EXPECT_EQ(mixed, cpu_only);
  EXPECT_GT(device->batches.load(), 0);
  EXPECT_EQ(metrics.tiles_fallen_back(0), static_cast<std::uint64_t>(device->batched_tiles.load()))
      << "every tile of a failed batch goes to the CPU";
  EXPECT_EQ(metrics.tiles_rendered_by(1), 0u);
  EXPECT_EQ(metrics.tiles_rendered_by(0), 16u);
}

TEST(SchedulerDevices, RenderDeviceKeepsAJobOnTheCpuOrOnTheDevices) {
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kRender);
  SceneDescription cpu = tiny_description(32, 32, 8);
  cpu.render.device = RenderDevice::kCpu;
  render_with(cpu, {device});
  EXPECT_EQ(device->attempts.load(), 0);

  SceneDescription gpu = tiny_description(32, 32, 8);  // 16 tiles
  gpu.render.device = RenderDevice::kGpu;
  const auto on_device = render_with(gpu, {device});
  EXPECT_EQ(device->attempts.load(), 16);  // the CPU worker prepared the job and took none
  EXPECT_EQ(on_device, render_with(tiny_description(32, 32, 8), {}));
}

TEST(SchedulerDevices, AGpuJobFailsSayingWhyWhenNoDeviceTakesIt) {
  SceneDescription gpu = tiny_description(16, 16, 8);
  gpu.render.device = RenderDevice::kGpu;
  for (const bool with_device : {false, true}) {
    auto job = make_job("gpu only", 0, gpu);
    SchedulerOptions options;
    options.threads = 1;
    if (with_device)
      options.devices = {std::make_shared<StandInDevice>(StandInDevice::Mode::kRefuse)};
    Scheduler scheduler(options);
    scheduler.submit(job, gpu);
    scheduler.start();
    scheduler.wait_idle();
    EXPECT_EQ(job->state(), JobState::kFailed);
    EXPECT_EQ(job->info().error,
              with_device ? "scene preparation failed: render.device is gpu, but no GPU of this "
                            "daemon takes the scene"
                          : "scene preparation failed: render.device is gpu, but this daemon "
                            "renders on no GPU");
  }
}

TEST(SchedulerDevices, JobsADeviceCannotRenderStayOnTheCpu) {
  auto refusing = std::make_shared<StandInDevice>(StandInDevice::Mode::kRefuse);
  render_with(tiny_description(32, 32, 8), {refusing});
  EXPECT_EQ(refusing->attempts.load(), 0);

  // Progressive passes are the CPU's: the device path renders one-pass tiles.
  auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kRender);
  SceneDescription with_passes = tiny_description(32, 32, 8);
  with_passes.render.samples_per_pixel = 4;
  with_passes.render.passes = 2;
  render_with(with_passes, {device});
  EXPECT_EQ(device->attempts.load(), 0);
}

// A job with AOVs renders on the device too: every plane the job asks for comes back from
// it (in batches as well), and the tiles equal the CPU's, AOV channels included.
TEST(SchedulerDevices, AnAovJobRendersOnTheDeviceWithEveryPlane) {
  SceneDescription scene = tiny_description(64, 48, 8);  // 48 tiles
  scene.render.aovs = kAllAovs;
  const auto cpu_only = render_with(scene, {}, nullptr, nullptr, true);
  for (const std::size_t batch : {std::size_t{0}, std::size_t{4 * 64}}) {
    SCOPED_TRACE(batch);
    auto device = std::make_shared<StandInDevice>(StandInDevice::Mode::kRender, batch);
    std::uint32_t done = 0;
    const auto mixed = render_with(scene, {device}, &done, nullptr, true);
    EXPECT_EQ(done, 48u);
    EXPECT_GT(device->attempts.load(), 0);
    ASSERT_EQ(mixed.size(), cpu_only.size());
    for (std::size_t t = 0; t < mixed.size(); ++t) {
      ASSERT_EQ(mixed[t].size(), 64u * output_channels(kAllAovs).size()) << "tile " << t;
      EXPECT_EQ(mixed[t], cpu_only[t]) << "tile " << t;
    }
  }
}

}  // namespace
}  // namespace tessera::server
