#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/job_store.hpp"
#include "tessera/render/tile.hpp"

namespace tessera::server {

struct JobProgress {
  std::uint32_t tiles_done = 0;
  std::uint32_t tiles_total = 0;
  std::uint64_t rays_traced = 0;
  double elapsed_seconds = 0.0;  // since the job started running
  // Rays over the time spent rendering: elapsed time less the scene preparation, so a job
  // whose BVH took a minute to build does not report a fraction of its real rate.
  double rays_per_second = 0.0;
  double eta_seconds = 0.0;  // 0 when unknown or finished
};

// A consistent copy of a job's observable state.
struct JobInfo {
  std::string id;
  std::string name;
  std::string submitter;
  int priority = 0;
  JobState state = JobState::kQueued;
  RenderSettings settings;  // defaults filled in
  JobProgress progress;
  std::string error;          // why it failed, when kFailed
  std::string cancel_reason;  // why it was cancelled, when kCancelled
  std::int64_t submitted_unix_ms = 0;
  std::int64_t finished_unix_ms = 0;  // 0 until finished
  JobLabels labels;
  std::string request_id;  // SubmitJobRequest.request_id; empty: none
};

JobInfo job_info(const JobRecord& record, std::int64_t now_ms);
// The progress a tile reports: the job's as it was when the tile was stored.
JobProgress tile_progress(const JobRecord& job, const StoredTile& tile);

// What a subscriber gets from wait_for_tiles: how many tiles are stored (they are read
// from the store by ordinal) and, once the job has finished, its final state. A finished
// job gains no more tiles, so a subscriber that has sent `tiles_done` tiles and sees
// `finished` has sent every tile exactly once.
struct TileUpdate {
  std::uint32_t tiles_done = 0;
  bool finished = false;
  JobState state = JobState::kQueued;
  std::string error;          // when kFailed
  std::string cancel_reason;  // when kCancelled
};

enum class CancelResult { kCancelled, kAlreadyCancelled, kAlreadyFinished };
enum class AddTileResult { kDropped, kStored, kCompletedJob };
// Pause, resume and retry: done now, already so (nothing changed), or refused in the job's
// current state.
enum class ControlResult { kDone, kAlready, kRefused };

// Told of each change of a job's state, and of each UpdateJob, with the record after it.
// Called under the job's lock, so one job's changes arrive in order; must be quick and must
// not call the job.
class JobListener {
 public:
  virtual ~JobListener() = default;
  virtual void job_changed(const JobRecord& job) = 0;
};

// A job live in this daemon: its record as last written to the store, and a condition
// variable for subscribers. Every transition is written to the store first, under this
// job's lock, so the cached record never runs ahead of what a restart would find.
// Finished tiles are not kept here but read from the store. Thread-safe.
class Job {
 public:
  Job(JobStore& store, JobRecord record, JobListener* listener = nullptr);
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  const std::string& id() const { return id_; }
  const std::string& name() const { return name_; }
  // Both may change (UpdateJob), so the submitter is a copy.
  std::string submitter() const;
  int priority() const { return priority_.load(std::memory_order_relaxed); }
  std::int64_t sequence() const { return sequence_; }
  const RenderSettings& settings() const { return settings_; }

  JobInfo info() const;
  JobRecord record() const;
  JobState state() const;
  bool finished() const { return is_finished(state()); }

  // Transitions used by the scheduler. They change nothing when the job has already
  // finished (typically: cancelled meanwhile), and mark_running and fail then return false.
  // mark_running also accepts a job already running (resumed after a restart).
  bool mark_running();
  // Claims tile `index` for `owner` in the store; false when it is stored already or
  // claimed by another owner.
  bool claim_tile(std::uint32_t index, const std::string& owner);
  void release_tile(std::uint32_t index, const std::string& owner);
  // Stores a rendered tile; the job completes with its last tile. A job that is no longer
  // running drops the tile.
  AddTileResult add_tile(const TileRect& rect, const std::string& owner,
                         const std::vector<std::uint8_t>& exr, std::uint64_t rays);
  // The same for one pass of a tile of a job with passes: `index` is the pass's store
  // index (job_passes.hpp), and the tile's accumulated state is stored (or, after its last
  // pass, dropped) with it.
  AddTileResult add_tile_pass(std::uint32_t index, const std::string& owner,
                              const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                              const TilePassState& state, bool last_pass);
  // The tile's accumulated state between its passes (see JobStore::tile_pass_state).
  std::optional<TilePassState> tile_pass_state(std::uint32_t tile) const;
  bool fail(std::string error);
  // Records time spent preparing the job's scene (JobRecord::prepare_ms).
  void add_prepare_time(std::chrono::milliseconds took);
  CancelResult cancel(std::string reason = {});

  // Job control (RPCs). Pause: queued or running -> paused (kRefused once finished); tiles
  // in flight are not stopped and are kept. Resume: paused -> queued (kAlready when queued
  // or running). Retry: failed or cancelled -> queued with its tiles kept (kRefused in any
  // other state). After resume and retry the scheduler must be given the job again.
  ControlResult pause();
  ControlResult resume();
  ControlResult retry();
  JobInfo update(const JobUpdate& update);
  // One more failed attempt at tile `index`; returns the failed attempts so far.
  std::uint32_t record_tile_failure(std::uint32_t index);

  // Tiles already stored (after a restart: those not to render again).
  std::vector<std::uint32_t> stored_tile_indices() const;
  // Stored tiles after the first `after_ordinal`, at most `limit`, in completion order.
  std::vector<StoredTile> tiles_after(std::uint32_t after_ordinal, std::size_t limit) const;

  // Blocks until more than `already_seen` tiles are stored, the job finishes, or `timeout`
  // passes (so a caller can check whether its client is still there).
  TileUpdate wait_for_tiles(std::size_t already_seen, std::chrono::milliseconds timeout) const;

  // Raised when the job finishes and when the daemon stops: a tile being rendered checks it
  // and gives up. A tile rendered while it was raised is incomplete and must not be stored.
  const std::atomic<bool>& stop_flag() const { return stop_; }
  bool stop_requested() const { return stop_.load(std::memory_order_relaxed); }
  void request_stop() { stop_.store(true, std::memory_order_relaxed); }
  // Counts retries: a tile that started in an earlier run may have been cut short by the
  // flag that retry lowered, so it must not be stored. Read stop_requested() first, then
  // this (retry changes them in the other order).
  std::uint64_t run() const { return run_.load(); }

 private:
  // `announce`: tell the listener even when the state did not change (an update).
  void set_locked(const JobRecord& record, bool announce = false);
  AddTileResult commit(std::uint32_t index, const std::string& owner,
                       const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                       const TilePassState* state, bool last_pass);

  JobStore& store_;
  JobListener* const listener_;
  const std::string id_;
  const std::string name_;
  std::atomic<int> priority_;
  const std::int64_t sequence_;
  const RenderSettings settings_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  JobRecord record_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> run_{0};
};

std::int64_t unix_millis_now();

}  // namespace tessera::server
