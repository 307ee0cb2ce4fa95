#pragma once
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "server/job.hpp"

namespace tessera::server {

// Which jobs a watcher is told about; every field set must match, none set matches all.
struct WatchFilter {
  std::string job_id;
  std::string submitter;
  std::optional<std::string> label_key;
  std::optional<std::string> label_value;  // only with label_key

  bool matches(const JobRecord& job) const;
};

// One event for a watcher: the job after a change, or its last known state when deleted.
struct JobChange {
  JobRecord job;
  bool deleted = false;
  bool snapshot = false;  // part of the opening snapshot
};

// Why a watcher was dropped.
enum class WatchDrop { kNone, kBufferFull, kWriteTimeout };

// Fans job changes out to WatchJobs streams. Each watcher has a bounded buffer: publishing
// never blocks (it runs under a job's lock, on workers and RPC threads). A watcher whose
// buffer overflows, or whose client leaves one write unread for longer than the write
// timeout, is dropped: its `cancel` callback ends the call (a blocked write returns), so a
// client that stops reading holds neither a worker nor a thread for longer than that.
// Thread-safe.
class JobWatchHub final : public JobListener {
 public:
  struct Options {
    std::size_t buffer_events = 1024;  // events waiting for one watcher, beyond its snapshot
    std::chrono::milliseconds write_timeout{10'000};
  };

  class Watcher {
   public:
    // The next event, waiting up to `timeout`; nothing on timeout or once dropped.
    std::optional<JobChange> next(std::chrono::milliseconds timeout);
    WatchDrop dropped() const;
    // Bracket each write to the client, so the hub can time it.
    void begin_write();
    void end_write();

   private:
    friend class JobWatchHub;
    WatchFilter filter_;
    std::function<void()> cancel_;
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<JobChange> events_;
    std::size_t capacity_ = 0;
    WatchDrop dropped_ = WatchDrop::kNone;
    std::optional<std::chrono::steady_clock::time_point> write_started_;
  };

  explicit JobWatchHub(Options options);
  ~JobWatchHub() override;
  JobWatchHub(const JobWatchHub&) = delete;
  JobWatchHub& operator=(const JobWatchHub&) = delete;

  // Registers a watcher whose buffer opens with `snapshot()`'s jobs that match `filter`;
  // `snapshot` runs with publishing held back, so no change is missed between it and the
  // events that follow (one may repeat a state the snapshot already showed). `snapshot`
  // must read the store only. `cancel` ends the watcher's call; it must not block.
  std::shared_ptr<Watcher> subscribe(WatchFilter filter,
                                     const std::function<std::vector<JobRecord>()>& snapshot,
                                     std::function<void()> cancel);
  void unsubscribe(const std::shared_ptr<Watcher>& watcher);

  void job_changed(const JobRecord& job) override;
  // `job` is the last known record; for jobs deleted by retention only the id is known.
  void job_deleted(const JobRecord& job);

  std::size_t watcher_count() const;
  const Options& options() const { return options_; }

 private:
  void publish(const JobChange& change);
  void watchdog_loop();
  static void drop(Watcher& watcher, WatchDrop why);  // under watcher.mutex_

  const Options options_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Watcher>> watchers_;
  std::condition_variable stop_cv_;
  bool stopping_ = false;
  std::thread watchdog_;
};

}  // namespace tessera::server
