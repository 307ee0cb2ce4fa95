// JobWatchHub: filters, the opening snapshot, and the two ways a watcher is dropped (its
// buffer overflows; one write to it waits past the write timeout) without ever blocking
// the publisher.
#include "server/job_watch.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace tessera::server {
namespace {

using namespace std::chrono_literals;

JobRecord job(const std::string& id, JobState state, const std::string& submitter = "ana",
              JobLabels labels = {}) {
  JobRecord r;
  r.id = id;
  r.state = state;
  r.submitter = submitter;
  r.labels = std::move(labels);
  r.tiles_total = 1;
  return r;
}

WatchFilter filter(std::string id, std::string submitter = "",
                   std::optional<std::string> key = std::nullopt,
                   std::optional<std::string> value = std::nullopt) {
  WatchFilter f;
  f.job_id = std::move(id);
  f.submitter = std::move(submitter);
  f.label_key = std::move(key);
  f.label_value = std::move(value);
  return f;
}

TEST(WatchFilter, EveryFieldSetMustMatch) {
  const JobRecord a = job("a", JobState::kQueued, "ana", {{"shot", "010"}});
  EXPECT_TRUE(WatchFilter{}.matches(a));
  EXPECT_TRUE(filter("a").matches(a));
  EXPECT_FALSE(filter("b").matches(a));
  EXPECT_FALSE(filter("", "bob").matches(a));
  EXPECT_TRUE(filter("", "", "shot").matches(a));
  EXPECT_TRUE(filter("", "", "shot", "010").matches(a));
  EXPECT_FALSE(filter("", "", "shot", "020").matches(a));
  EXPECT_FALSE(filter("a", "bob").matches(a));
}

TEST(JobWatchHub, StartsWithTheMatchingSnapshotThenSendsChangesInOrder) {
  JobWatchHub hub({.buffer_events = 8, .write_timeout = 10s});
  const auto watcher = hub.subscribe(
      filter("", "ana"),
      [] {
        return std::vector<JobRecord>{job("a", JobState::kRunning),
                                      job("b", JobState::kQueued, "bob")};
      },
      [] {});
  hub.job_changed(job("c", JobState::kQueued, "bob"));  // filtered out
  hub.job_changed(job("a", JobState::kPaused));
  hub.job_deleted(job("a", JobState::kCancelled));
  auto first = watcher->next(1s);
  ASSERT_TRUE(first);
  EXPECT_TRUE(first->snapshot);
  EXPECT_EQ(first->job.state, JobState::kRunning);
  auto second = watcher->next(1s);
  ASSERT_TRUE(second);
  EXPECT_FALSE(second->snapshot);
  EXPECT_EQ(second->job.state, JobState::kPaused);
  auto third = watcher->next(1s);
  ASSERT_TRUE(third);
  EXPECT_TRUE(third->deleted);
  EXPECT_FALSE(watcher->next(10ms));
  EXPECT_EQ(hub.watcher_count(), 1u);
  hub.unsubscribe(watcher);
  EXPECT_EQ(hub.watcher_count(), 0u);
}

TEST(JobWatchHub, AWatcherWhoseBufferOverflowsIsDroppedWithoutBlockingThePublisher) {
  JobWatchHub hub({.buffer_events = 2, .write_timeout = 10s});
  std::atomic<int> cancels{0};
  const auto watcher = hub.subscribe({}, {}, [&] { ++cancels; });
  for (int i = 0; i < 5; ++i) hub.job_changed(job("a", JobState::kRunning));  // nobody reads
  EXPECT_EQ(watcher->dropped(), WatchDrop::kBufferFull);
  EXPECT_EQ(cancels.load(), 1);
  EXPECT_FALSE(watcher->next(10ms));
}

TEST(JobWatchHub, AWriteWaitingPastTheTimeoutDropsTheWatcher) {
  JobWatchHub hub({.buffer_events = 8, .write_timeout = 50ms});
  std::atomic<int> cancels{0};
  const auto watcher = hub.subscribe({}, {}, [&] { ++cancels; });
  watcher->begin_write();  // a write the client never takes
  const auto give_up = std::chrono::steady_clock::now() + 30s;
  while (watcher->dropped() == WatchDrop::kNone && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(5ms);
  EXPECT_EQ(watcher->dropped(), WatchDrop::kWriteTimeout);
  EXPECT_EQ(cancels.load(), 1);
  watcher->end_write();

  // A write that returns in time keeps the watcher.
  const auto quick = hub.subscribe({}, {}, [] {});
  quick->begin_write();
  quick->end_write();
  std::this_thread::sleep_for(150ms);
  EXPECT_EQ(quick->dropped(), WatchDrop::kNone);
}

}  // namespace
}  // namespace tessera::server
