#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "tessera/render/tile.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera::server {

enum class JobState { kQueued, kRunning, kCompleted, kFailed, kCancelled };

const char* to_string(JobState state);
inline bool is_finished(JobState state) {
  return state == JobState::kCompleted || state == JobState::kFailed ||
         state == JobState::kCancelled;
}

struct JobProgress {
  std::uint32_t tiles_done = 0;
  std::uint32_t tiles_total = 0;
  std::uint64_t rays_traced = 0;
  double elapsed_seconds = 0.0;  // since the job started running
  double rays_per_second = 0.0;
  double eta_seconds = 0.0;  // 0 when unknown or finished
};

// One rendered tile as every subscriber receives it. The EXR bytes are shared, not copied
// per subscriber.
struct FinishedTile {
  TileRect rect;
  std::shared_ptr<const std::vector<std::uint8_t>> exr;
  JobProgress progress;  // the job's progress including this tile
};

// A consistent copy of a job's observable state.
struct JobInfo {
  std::string id;
  std::string name;
  int priority = 0;
  JobState state = JobState::kQueued;
  RenderSettings settings;  // defaults filled in
  JobProgress progress;
  std::string error;          // why it failed, when kFailed
  std::string cancel_reason;  // why it was cancelled, when kCancelled
  std::int64_t submitted_unix_ms = 0;
  std::int64_t finished_unix_ms = 0;  // 0 until finished
};

// What a subscriber gets from wait_for_tiles: the tiles after the ones it already has and,
// once the job has finished, its final state. A finished job gains no more tiles, so a
// subscriber that has sent `tiles` and sees `finished` has sent every tile exactly once.
struct TileUpdate {
  std::vector<FinishedTile> tiles;
  bool finished = false;
  JobState state = JobState::kQueued;
  std::string error;          // when kFailed
  std::string cancel_reason;  // when kCancelled
};

enum class CancelResult { kCancelled, kAlreadyCancelled, kAlreadyFinished };
enum class AddTileResult { kDropped, kStored, kCompletedJob };

// One render job's record: identity, state machine, progress and finished tiles. All
// members are thread-safe; the scheduler drives the transitions and any number of
// subscribers wait for tiles. The scene itself is not kept here (the scheduler owns it
// until it is prepared).
class Job {
 public:
  Job(std::string id, std::string name, int priority, RenderSettings settings,
      std::uint32_t tiles_total, std::int64_t submitted_unix_ms);
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  const std::string& id() const { return id_; }
  const std::string& name() const { return name_; }
  int priority() const { return priority_; }
  const RenderSettings& settings() const { return settings_; }

  JobInfo info() const;
  JobState state() const;
  bool finished() const { return is_finished(state()); }

  // Transitions used by the scheduler. They change nothing when the job has already
  // finished (typically: cancelled meanwhile), and mark_running and fail then return false.
  bool mark_running();
  // Stores a rendered tile; the job completes with its last tile. A job that is no longer
  // running drops the tile.
  AddTileResult add_tile(const TileRect& rect, std::vector<std::uint8_t> exr, std::uint64_t rays);
  bool fail(std::string error);

  CancelResult cancel(std::string reason = {});

  // Blocks until there are tiles beyond the first `already_seen`, the job finishes, or
  // `timeout` passes (so a caller can check whether its client is still there).
  TileUpdate wait_for_tiles(std::size_t already_seen, std::chrono::milliseconds timeout) const;

 private:
  using Clock = std::chrono::steady_clock;

  JobProgress progress_locked(Clock::time_point now) const;
  void finish_locked(JobState state);

  const std::string id_;
  const std::string name_;
  const int priority_;
  const RenderSettings settings_;
  const std::int64_t submitted_unix_ms_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  JobState state_ = JobState::kQueued;
  std::uint32_t tiles_total_;
  std::uint64_t rays_traced_ = 0;
  Clock::time_point started_{};
  Clock::time_point finished_{};
  std::int64_t finished_unix_ms_ = 0;
  std::string error_;
  std::string cancel_reason_;
  std::vector<FinishedTile> tiles_;
};

std::int64_t unix_millis_now();

}  // namespace tessera::server
