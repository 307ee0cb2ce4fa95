#include "server/job.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <stdexcept>

#include "server/job_id.hpp"
#include "server/sqlite_job_store.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;

// Jobs over a private in-memory store.
class JobTest : public ::testing::Test {
 protected:
  std::shared_ptr<Job> make_job(const std::string& id, std::uint32_t tiles = 2) {
    JobRecord record;
    record.id = id;
    record.name = "name";
    record.priority = 1;
    record.settings.width = 8 * tiles;
    record.settings.height = 8;
    record.settings.tile_size = 8;
    record.tiles_total = tiles;
    record.submitted_unix_ms = 1234;
    return std::make_shared<Job>(store_, store_.create_job(record, SceneSource{"scene", "s"}));
  }

  SqliteJobStore store_{":memory:"};
};

TileRect rect(std::uint32_t index) {
  return TileRect{index, index * 8, 0, 8, 8};
}

TEST_F(JobTest, CompletesWithItsLastTileAndCountsRays) {
  auto job = make_job("job-a", 2);
  EXPECT_EQ(job->state(), JobState::kQueued);
  EXPECT_EQ(job->add_tile(rect(0), "w", {1, 2, 3}, 10), AddTileResult::kDropped);  // not running
  ASSERT_TRUE(job->mark_running());
  EXPECT_EQ(job->add_tile(rect(0), "w", {1, 2, 3}, 10), AddTileResult::kStored);
  JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kRunning);
  EXPECT_EQ(info.progress.tiles_done, 1u);
  EXPECT_EQ(info.progress.rays_traced, 10u);
  EXPECT_EQ(info.finished_unix_ms, 0);
  EXPECT_EQ(job->add_tile(rect(1), "w", {4}, 32), AddTileResult::kCompletedJob);
  info = job->info();
  EXPECT_EQ(info.state, JobState::kCompleted);
  EXPECT_EQ(info.progress.tiles_done, 2u);
  EXPECT_EQ(info.progress.rays_traced, 42u);
  EXPECT_EQ(info.progress.eta_seconds, 0.0);
  EXPECT_EQ(info.submitted_unix_ms, 1234);
  EXPECT_GT(info.finished_unix_ms, 0);
  EXPECT_FALSE(job->fail("too late"));
  EXPECT_EQ(job->cancel(), CancelResult::kAlreadyFinished);
  EXPECT_TRUE(job->stop_requested());

  // What the job holds is what the store holds.
  const auto stored = store_.find_job("job-a");
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->state, JobState::kCompleted);
  EXPECT_EQ(stored->rays_traced, 42u);
  const auto tiles = job->tiles_after(0, 10);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].exr, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_EQ(tiles[1].ordinal, 2u);
  EXPECT_EQ(tiles[1].rays_after, 42u);
}

TEST_F(JobTest, CancelIsIdempotentAndDropsLaterTiles) {
  auto job = make_job("job-b", 3);
  ASSERT_TRUE(job->mark_running());
  EXPECT_EQ(job->add_tile(rect(0), "w", {1}, 1), AddTileResult::kStored);
  EXPECT_FALSE(job->stop_requested());
  EXPECT_EQ(job->cancel("by request"), CancelResult::kCancelled);
  EXPECT_TRUE(job->stop_requested());  // reaches the tiles being rendered
  EXPECT_EQ(job->cancel("again"), CancelResult::kAlreadyCancelled);
  EXPECT_EQ(job->add_tile(rect(1), "w", {1}, 1), AddTileResult::kDropped);
  const JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kCancelled);
  EXPECT_EQ(info.cancel_reason, "by request");
  EXPECT_EQ(info.progress.tiles_done, 1u);
  EXPECT_FALSE(job->fail("after cancel"));
  EXPECT_EQ(store_.find_job("job-b")->cancel_reason, "by request");
}

TEST_F(JobTest, FailureKeepsTheMessage) {
  auto job = make_job("job-c");
  ASSERT_TRUE(job->mark_running());
  EXPECT_TRUE(job->fail("boom"));
  EXPECT_EQ(job->info().error, "boom");
  EXPECT_EQ(job->state(), JobState::kFailed);
  EXPECT_EQ(job->cancel(), CancelResult::kAlreadyFinished);
  EXPECT_EQ(store_.find_job("job-c")->error, "boom");
}

TEST_F(JobTest, WaitForTilesReportsStoredTilesAndTheEnd) {
  auto job = make_job("job-d", 2);
  TileUpdate update = job->wait_for_tiles(0, 1ms);  // times out: nothing yet
  EXPECT_EQ(update.tiles_done, 0u);
  EXPECT_FALSE(update.finished);
  ASSERT_TRUE(job->mark_running());
  job->add_tile(rect(0), "w", {7}, 1);
  update = job->wait_for_tiles(0, 1s);
  EXPECT_EQ(update.tiles_done, 1u);
  EXPECT_FALSE(update.finished);
  job->add_tile(rect(1), "w", {8}, 1);
  update = job->wait_for_tiles(1, 1s);
  EXPECT_EQ(update.tiles_done, 2u);
  EXPECT_TRUE(update.finished);
  EXPECT_EQ(update.state, JobState::kCompleted);
  const auto second = job->tiles_after(1, 10);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].index, 1u);
  EXPECT_EQ(second[0].exr, std::vector<std::uint8_t>{8});
}

TEST(JobIdGenerator, IdsAreShortHexAndUnique) {
  JobIdGenerator ids;
  const std::regex format("job-[0-9a-f]{12}");
  std::set<std::string> seen;
  for (int i = 0; i < 20'000; ++i) {
    const std::string id = ids.next();
    ASSERT_TRUE(std::regex_match(id, format)) << id;
    ASSERT_TRUE(seen.insert(id).second) << "repeated " << id;
  }
}

TEST(JobIdGenerator, DifferentKeysGiveDifferentSequences) {
  JobIdGenerator a(1), b(2);
  EXPECT_NE(a.next(), b.next());
}

}  // namespace
}  // namespace tessera::server
