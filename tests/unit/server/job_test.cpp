#include "server/job.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <stdexcept>

#include "server/job_id.hpp"
#include "server/job_store.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<Job> make_job(const std::string& id, std::uint32_t tiles = 2) {
  return std::make_shared<Job>(id, "name", 1, RenderSettings{}, tiles, 1234);
}

TileRect rect(std::uint32_t index) {
  return TileRect{index, index * 8, 0, 8, 8};
}

TEST(Job, CompletesWithItsLastTileAndCountsRays) {
  auto job = make_job("job-a", 2);
  EXPECT_EQ(job->state(), JobState::kQueued);
  EXPECT_EQ(job->add_tile(rect(0), {1, 2, 3}, 10), AddTileResult::kDropped);  // not running
  ASSERT_TRUE(job->mark_running());
  EXPECT_FALSE(job->mark_running());
  EXPECT_EQ(job->add_tile(rect(0), {1, 2, 3}, 10), AddTileResult::kStored);
  JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kRunning);
  EXPECT_EQ(info.progress.tiles_done, 1u);
  EXPECT_EQ(info.progress.rays_traced, 10u);
  EXPECT_EQ(info.finished_unix_ms, 0);
  EXPECT_EQ(job->add_tile(rect(1), {4}, 32), AddTileResult::kCompletedJob);
  info = job->info();
  EXPECT_EQ(info.state, JobState::kCompleted);
  EXPECT_EQ(info.progress.tiles_done, 2u);
  EXPECT_EQ(info.progress.rays_traced, 42u);
  EXPECT_EQ(info.progress.eta_seconds, 0.0);
  EXPECT_EQ(info.submitted_unix_ms, 1234);
  EXPECT_GT(info.finished_unix_ms, 0);
  EXPECT_FALSE(job->fail("too late"));
  EXPECT_EQ(job->cancel(), CancelResult::kAlreadyFinished);
}

TEST(Job, CancelIsIdempotentAndDropsLaterTiles) {
  auto job = make_job("job-b", 3);
  ASSERT_TRUE(job->mark_running());
  EXPECT_EQ(job->add_tile(rect(0), {1}, 1), AddTileResult::kStored);
  EXPECT_EQ(job->cancel("by request"), CancelResult::kCancelled);
  EXPECT_EQ(job->cancel("again"), CancelResult::kAlreadyCancelled);
  EXPECT_EQ(job->add_tile(rect(1), {1}, 1), AddTileResult::kDropped);
  const JobInfo info = job->info();
  EXPECT_EQ(info.state, JobState::kCancelled);
  EXPECT_EQ(info.cancel_reason, "by request");
  EXPECT_EQ(info.progress.tiles_done, 1u);
  EXPECT_FALSE(job->fail("after cancel"));
}

TEST(Job, FailureKeepsTheMessage) {
  auto job = make_job("job-c");
  ASSERT_TRUE(job->mark_running());
  EXPECT_TRUE(job->fail("boom"));
  EXPECT_EQ(job->info().error, "boom");
  EXPECT_EQ(job->state(), JobState::kFailed);
  EXPECT_EQ(job->cancel(), CancelResult::kAlreadyFinished);
}

TEST(Job, WaitForTilesReturnsOnlyUnseenTilesAndTheEnd) {
  auto job = make_job("job-d", 2);
  TileUpdate update = job->wait_for_tiles(0, 1ms);  // times out: nothing yet
  EXPECT_TRUE(update.tiles.empty());
  EXPECT_FALSE(update.finished);
  ASSERT_TRUE(job->mark_running());
  job->add_tile(rect(0), {7}, 1);
  update = job->wait_for_tiles(0, 1s);
  ASSERT_EQ(update.tiles.size(), 1u);
  EXPECT_EQ((*update.tiles[0].exr)[0], 7);
  EXPECT_FALSE(update.finished);
  job->add_tile(rect(1), {8}, 1);
  update = job->wait_for_tiles(1, 1s);
  ASSERT_EQ(update.tiles.size(), 1u);
  EXPECT_EQ(update.tiles[0].rect.index, 1u);
  EXPECT_TRUE(update.finished);
  EXPECT_EQ(update.state, JobState::kCompleted);
}

TEST(JobStore, FindsJobsAndListsNewestFirst) {
  InMemoryJobStore store;
  store.add(make_job("job-1"));
  store.add(make_job("job-2"));
  store.add(make_job("job-3"));
  EXPECT_EQ(store.find("job-2")->id(), "job-2");
  EXPECT_EQ(store.find("job-9"), nullptr);
  const auto jobs = store.list();
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0]->id(), "job-3");
  EXPECT_EQ(jobs[2]->id(), "job-1");
  EXPECT_THROW(store.add(make_job("job-2")), std::invalid_argument);
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
