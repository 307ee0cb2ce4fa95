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
    case JobState::kPaused:
      return "paused";
  }
  return "unknown";
}

std::int64_t unix_millis_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

namespace {

// Progress of a job that had `done` of `total` tiles and `rays` when `elapsed_ms` had passed
// since it started, `prepare_ms` of which went to preparing its scene.
JobProgress progress_at(std::uint32_t done, std::uint32_t total, std::uint64_t rays,
                        std::int64_t elapsed_ms, std::int64_t prepare_ms, bool running) {
  JobProgress p;
  p.tiles_done = done;
  p.tiles_total = total;
  p.rays_traced = rays;
  p.elapsed_seconds = static_cast<double>(std::max<std::int64_t>(elapsed_ms, 0)) / 1000.0;
  // Rendering time only: the preparation traced no rays and is not repeated per tile.
  const double rendering_seconds =
      static_cast<double>(std::max<std::int64_t>(elapsed_ms - prepare_ms, 0)) / 1000.0;
  if (rendering_seconds > 0.0) p.rays_per_second = static_cast<double>(rays) / rendering_seconds;
  if (running && done > 0 && done < total)
    p.eta_seconds = rendering_seconds * (total - done) / done;
  return p;
}

}  // namespace

JobInfo job_info(const JobRecord& r, std::int64_t now_ms) {
  JobInfo info;
  info.id = r.id;
  info.name = r.name;
  info.submitter = r.submitter;
  info.priority = r.priority;
  info.state = r.state;
  info.settings = r.settings;
  const std::int64_t end = is_finished(r.state) ? r.finished_unix_ms : now_ms;
  const std::int64_t elapsed = r.started_unix_ms == 0 ? 0 : end - r.started_unix_ms;
  info.progress = progress_at(r.tiles_done, r.tiles_total, r.rays_traced, elapsed, r.prepare_ms,
                              r.state == JobState::kRunning);
  info.error = r.error;
  info.cancel_reason = r.cancel_reason;
  info.submitted_unix_ms = r.submitted_unix_ms;
  info.finished_unix_ms = r.finished_unix_ms;
  info.labels = r.labels;
  info.request_id = r.request_id;
  return info;
}

JobProgress tile_progress(const JobRecord& job, const StoredTile& tile) {
  const std::int64_t elapsed =
      job.started_unix_ms == 0 ? 0 : tile.finished_unix_ms - job.started_unix_ms;
  return progress_at(tile.ordinal, job.tiles_total, tile.rays_after, elapsed, job.prepare_ms, true);
}

Job::Job(JobStore& store, JobRecord record, JobListener* listener)
    : store_(store),
      listener_(listener),
      id_(record.id),
      name_(record.name),
      priority_(record.priority),
      sequence_(record.sequence),
      settings_(record.settings),
      record_(std::move(record)) {
  if (is_finished(record_.state)) stop_ = true;
}

void Job::set_locked(const JobRecord& record, bool announce) {
  const bool state_changed = record.state != record_.state;
  record_ = record;
  priority_.store(record_.priority, std::memory_order_relaxed);
  if (is_finished(record_.state)) stop_ = true;
  changed_.notify_all();
  if (listener_ && (state_changed || announce)) listener_->job_changed(record_);
}

std::string Job::submitter() const {
  std::lock_guard lock(mutex_);
  return record_.submitter;
}

JobInfo Job::info() const {
  std::lock_guard lock(mutex_);
  return job_info(record_, unix_millis_now());
}

JobRecord Job::record() const {
  std::lock_guard lock(mutex_);
  return record_;
}

JobState Job::state() const {
  std::lock_guard lock(mutex_);
  return record_.state;
}

void Job::add_prepare_time(std::chrono::milliseconds took) {
  std::lock_guard lock(mutex_);
  if (const auto updated = store_.add_prepare_time(id_, took.count())) set_locked(*updated);
}

bool Job::mark_running() {
  std::lock_guard lock(mutex_);
  if (is_finished(record_.state)) return false;
  const auto updated = store_.mark_running(id_, unix_millis_now());
  if (!updated) return false;
  set_locked(*updated);
  return true;
}

bool Job::claim_tile(std::uint32_t index, const std::string& owner) {
  // A lease long enough for any tile: only a store shared between daemons looks at it.
  constexpr std::int64_t kLeaseMs = 24 * 3600 * 1000;
  const std::int64_t now = unix_millis_now();
  return store_.claim_tile(id_, index, owner, now + kLeaseMs, now);
}

void Job::release_tile(std::uint32_t index, const std::string& owner) {
  store_.release_tile(id_, index, owner);
}

AddTileResult Job::add_tile(const TileRect& rect, const std::string& owner,
                            const std::vector<std::uint8_t>& exr, std::uint64_t rays) {
  return commit(rect.index, owner, exr, rays, nullptr, false);
}

AddTileResult Job::add_tile_pass(std::uint32_t index, const std::string& owner,
                                 const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                                 const TilePassState& state, bool last_pass) {
  return commit(index, owner, exr, rays, &state, last_pass);
}

std::optional<TilePassState> Job::tile_pass_state(std::uint32_t tile) const {
  return store_.tile_pass_state(id_, tile);
}

AddTileResult Job::commit(std::uint32_t index, const std::string& owner,
                          const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                          const TilePassState* state, bool last_pass) {
  std::lock_guard lock(mutex_);
  // A paused job keeps the tiles that were in flight when it was paused.
  if (record_.state != JobState::kRunning && record_.state != JobState::kPaused) {
    store_.release_tile(id_, index, owner);
    return AddTileResult::kDropped;  // cancelled or failed meanwhile
  }
  const std::int64_t now = unix_millis_now();
  const TileCommitResult result =
      state ? store_.commit_tile_pass(id_, index, owner, exr, rays, now, *state, last_pass)
            : store_.commit_tile(id_, index, owner, exr, rays, now);
  if (result.outcome == TileCommit::kJobNotRunning || result.outcome == TileCommit::kDuplicate)
    return AddTileResult::kDropped;
  set_locked(result.job);
  return result.outcome == TileCommit::kCompletedJob ? AddTileResult::kCompletedJob
                                                     : AddTileResult::kStored;
}

bool Job::fail(std::string error) {
  std::lock_guard lock(mutex_);
  if (is_finished(record_.state)) return false;
  const auto updated = store_.finish_job(id_, JobState::kFailed, error, unix_millis_now());
  if (!updated) return false;
  set_locked(*updated);
  return true;
}

CancelResult Job::cancel(std::string reason) {
  std::lock_guard lock(mutex_);
  if (record_.state == JobState::kCancelled) return CancelResult::kAlreadyCancelled;
  if (is_finished(record_.state)) return CancelResult::kAlreadyFinished;
  const auto updated = store_.finish_job(id_, JobState::kCancelled, reason, unix_millis_now());
  if (!updated) {
    // Finished in the store by someone else (another daemon sharing it): report that state.
    if (const auto current = store_.find_job(id_)) set_locked(*current);
    return record_.state == JobState::kCancelled ? CancelResult::kAlreadyCancelled
                                                 : CancelResult::kAlreadyFinished;
  }
  set_locked(*updated);
  return CancelResult::kCancelled;
}

ControlResult Job::pause() {
  std::lock_guard lock(mutex_);
  if (record_.state == JobState::kPaused) return ControlResult::kAlready;
  if (!is_runnable(record_.state)) return ControlResult::kRefused;
  const auto updated = store_.pause_job(id_);
  if (!updated) return ControlResult::kRefused;
  set_locked(*updated);
  return ControlResult::kDone;
}

ControlResult Job::resume() {
  std::lock_guard lock(mutex_);
  if (is_runnable(record_.state)) return ControlResult::kAlready;
  if (record_.state != JobState::kPaused) return ControlResult::kRefused;
  const auto updated = store_.resume_job(id_);
  if (!updated) return ControlResult::kRefused;
  set_locked(*updated);
  return ControlResult::kDone;
}

ControlResult Job::retry() {
  std::lock_guard lock(mutex_);
  if (record_.state != JobState::kFailed && record_.state != JobState::kCancelled)
    return ControlResult::kRefused;
  const auto updated = store_.retry_job(id_);
  if (!updated) return ControlResult::kRefused;
  // Tiles of the failed run that are still rendering were cut short by the raised flag and
  // are dropped; lowering it lets the new run's tiles render.
  ++run_;
  stop_ = false;
  set_locked(*updated);
  return ControlResult::kDone;
}

JobInfo Job::update(const JobUpdate& update) {
  std::lock_guard lock(mutex_);
  if (const auto updated = store_.update_job(id_, update)) set_locked(*updated, true);
  return job_info(record_, unix_millis_now());
}

std::uint32_t Job::record_tile_failure(std::uint32_t index) {
  return store_.record_tile_failure(id_, index);
}

std::vector<std::uint32_t> Job::stored_tile_indices() const {
  return store_.stored_tile_indices(id_);
}

std::vector<StoredTile> Job::tiles_after(std::uint32_t after_ordinal, std::size_t limit) const {
  return store_.tiles_after(id_, after_ordinal, limit);
}

TileUpdate Job::wait_for_tiles(std::size_t already_seen, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] {
    return record_.tiles_done > already_seen || is_finished(record_.state);
  });
  TileUpdate update;
  update.tiles_done = record_.tiles_done;
  update.finished = is_finished(record_.state);
  update.state = record_.state;
  update.error = record_.error;
  update.cancel_reason = record_.cancel_reason;
  return update;
}

}  // namespace tessera::server
