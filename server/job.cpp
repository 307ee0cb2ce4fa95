#include "server/job.hpp"

namespace tessera::server {

const char* to_string(JobState state) {
  switch (state) {
    case JobState::kQueued:
      return "queued";
    case JobState::kRunning:
      return "running";
    case JobState::kCompleted:
      return "completed";
    case JobState::kFailed:
      return "failed";
    case JobState::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

std::int64_t unix_millis_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

Job::Job(std::string id, std::string name, int priority, RenderSettings settings,
         std::uint32_t tiles_total, std::int64_t submitted_unix_ms)
    : id_(std::move(id)),
      name_(std::move(name)),
      priority_(priority),
      settings_(settings),
      submitted_unix_ms_(submitted_unix_ms),
      tiles_total_(tiles_total) {}

JobProgress Job::progress_locked(Clock::time_point now) const {
  JobProgress p;
  p.tiles_done = static_cast<std::uint32_t>(tiles_.size());
  p.tiles_total = tiles_total_;
  p.rays_traced = rays_traced_;
  if (state_ == JobState::kQueued || started_ == Clock::time_point{}) return p;
  const Clock::time_point end = is_finished(state_) ? finished_ : now;
  p.elapsed_seconds = std::chrono::duration<double>(end - started_).count();
  if (p.elapsed_seconds > 0.0)
    p.rays_per_second = static_cast<double>(rays_traced_) / p.elapsed_seconds;
  if (state_ == JobState::kRunning && p.tiles_done > 0 && p.tiles_done < p.tiles_total)
    p.eta_seconds = p.elapsed_seconds * (p.tiles_total - p.tiles_done) / p.tiles_done;
  return p;
}

void Job::finish_locked(JobState state) {
  state_ = state;
  finished_ = Clock::now();
  finished_unix_ms_ = unix_millis_now();
  changed_.notify_all();
}

JobInfo Job::info() const {
  std::lock_guard lock(mutex_);
  JobInfo info;
  info.id = id_;
  info.name = name_;
  info.priority = priority_;
  info.state = state_;
  info.settings = settings_;
  info.progress = progress_locked(Clock::now());
  info.error = error_;
  info.cancel_reason = cancel_reason_;
  info.submitted_unix_ms = submitted_unix_ms_;
  info.finished_unix_ms = finished_unix_ms_;
  return info;
}

JobState Job::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

bool Job::mark_running() {
  std::lock_guard lock(mutex_);
  if (state_ != JobState::kQueued) return false;
  state_ = JobState::kRunning;
  started_ = Clock::now();
  changed_.notify_all();
  return true;
}

AddTileResult Job::add_tile(const TileRect& rect, std::vector<std::uint8_t> exr,
                            std::uint64_t rays) {
  std::lock_guard lock(mutex_);
  if (state_ != JobState::kRunning)
    return AddTileResult::kDropped;  // cancelled or failed meanwhile
  rays_traced_ += rays;
  FinishedTile tile;
  tile.rect = rect;
  tile.exr = std::make_shared<const std::vector<std::uint8_t>>(std::move(exr));
  tiles_.push_back(std::move(tile));
  const bool last = tiles_.size() >= tiles_total_;
  if (last) finish_locked(JobState::kCompleted);
  // Computed after a possible completion, so the last tile reports elapsed time and no ETA.
  tiles_.back().progress = progress_locked(Clock::now());
  changed_.notify_all();
  return last ? AddTileResult::kCompletedJob : AddTileResult::kStored;
}

bool Job::fail(std::string error) {
  std::lock_guard lock(mutex_);
  if (is_finished(state_)) return false;
  if (started_ == Clock::time_point{}) started_ = Clock::now();
  error_ = std::move(error);
  finish_locked(JobState::kFailed);
  return true;
}

CancelResult Job::cancel(std::string reason) {
  std::lock_guard lock(mutex_);
  if (state_ == JobState::kCancelled) return CancelResult::kAlreadyCancelled;
  if (is_finished(state_)) return CancelResult::kAlreadyFinished;
  if (started_ == Clock::time_point{}) started_ = Clock::now();
  cancel_reason_ = std::move(reason);
  finish_locked(JobState::kCancelled);
  return CancelResult::kCancelled;
}

TileUpdate Job::wait_for_tiles(std::size_t already_seen, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout,
                    [&] { return tiles_.size() > already_seen || is_finished(state_); });
  TileUpdate update;
  if (already_seen < tiles_.size())
    update.tiles.assign(tiles_.begin() + static_cast<std::ptrdiff_t>(already_seen), tiles_.end());
  update.finished = is_finished(state_);
  update.state = state_;
  update.error = error_;
  update.cancel_reason = cancel_reason_;
  return update;
}

}  // namespace tessera::server
