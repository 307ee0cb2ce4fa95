#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tessera/scene/scene_description.hpp"

namespace tessera::server {

// The stored value of each state is its position here: new states go at the end.
enum class JobState { kQueued, kRunning, kCompleted, kFailed, kCancelled, kPaused };

const char* to_string(JobState state);
inline bool is_finished(JobState state) {
  return state == JobState::kCompleted || state == JobState::kFailed ||
         state == JobState::kCancelled;
}
// Whether workers may take the job's tiles (a paused job is unfinished but not runnable).
inline bool is_runnable(JobState state) {
  return state == JobState::kQueued || state == JobState::kRunning;
}

using JobLabels = std::map<std::string, std::string>;

// A job as the store keeps it: everything but its scene and tiles.
struct JobRecord {
  std::string id;
  std::string name;
  std::string submitter;  // who submitted it: fair scheduling and per-submitter caps
  int priority = 0;
  JobState state = JobState::kQueued;
  RenderSettings settings;  // defaults filled in
  // Store tiles: the job's tiles times its passes (job_passes.hpp), so with passes these
  // count tile passes.
  std::uint32_t tiles_total = 0;
  std::uint32_t tiles_done = 0;
  std::uint64_t rays_traced = 0;
  std::string error;          // why it failed, when kFailed
  std::string cancel_reason;  // why it was cancelled, when kCancelled
  std::int64_t submitted_unix_ms = 0;
  std::int64_t started_unix_ms = 0;   // 0 until a worker first picked it up
  std::int64_t finished_unix_ms = 0;  // 0 until finished
  // Time spent preparing the scene (conversion, BVH build), summed over the job's starts:
  // taken out of the elapsed time that rays per second divide by.
  std::int64_t prepare_ms = 0;
  // Submission order, assigned by the store, increasing across restarts: orders the queue
  // and ListJobs, and is the ListJobs page token.
  std::int64_t sequence = 0;
  JobLabels labels;
  // The SubmitJobRequest.request_id the job was created under (empty: none), and the
  // fingerprint of that request's scene and settings (request_id.hpp). The pair
  // (submitter at submission, request_id) names at most one job while the job exists.
  std::string request_id;
  std::string request_fingerprint;
};

// What UpdateJob changes; unset fields stay as they are.
struct JobUpdate {
  std::optional<int> priority;
  std::optional<std::string> submitter;
  std::vector<std::string> remove_labels;  // applied first
  JobLabels set_labels;
};

// The scene of a job as it was submitted: the serialized tessera.v1.Scene and the job's
// resolved tessera.v1.RenderSettings. Kept as bytes so the store does not depend on the
// scene model, and converted again when the job is prepared (also after a restart).
struct SceneSource {
  std::string scene_proto;
  std::string settings_proto;
};

// One finished tile. `ordinal` is its place in the job's completion order (1 for the first
// tile finished), the sequence number streams resume from; the rays and time are the job's
// totals when it was stored, so its progress can be reported at any later time.
struct StoredTile {
  std::uint32_t index = 0;
  std::uint32_t ordinal = 0;
  std::uint64_t rays_after = 0;
  std::int64_t finished_unix_ms = 0;
  std::vector<std::uint8_t> exr;
};

// A tile of a job with progressive passes between two of its passes: the accumulated state
// (tile_state_codec.hpp) after `passes_done` passes, kept by the store until its last pass
// is committed, so a restart continues the tile without rendering a finished pass again.
struct TilePassState {
  std::uint32_t tile = 0;  // index in the tile grid (not the store index of a pass)
  std::uint32_t passes_done = 0;
  std::vector<std::uint8_t> bytes;
};

enum class TileCommit {
  kStored,        // the tile is stored; the job has more to render
  kCompletedJob,  // the tile was the job's last: the job is now completed
  kDuplicate,     // the tile had been stored before; nothing changed but its counter
  kJobNotRunning  // the job is queued, finished or gone; nothing was stored
};

struct TileCommitResult {
  TileCommit outcome = TileCommit::kJobNotRunning;
  JobRecord job;  // after the commit (when the job exists)
};

struct JobQuery {
  std::size_t limit = 100;
  std::optional<std::int64_t> before_sequence;  // only jobs submitted before this one
  std::optional<JobState> state;
  std::optional<std::string> submitter;
  std::optional<std::string> name;  // exact match
  // Jobs with this label key, and (when label_value is set) this value.
  std::optional<std::string> label_key;
  std::optional<std::string> label_value;
};

// What retention keeps: finished jobs are deleted once finished longer than `ttl_ms` ago
// (0: no age limit), and the oldest finished ones are deleted while there are more than
// `max_jobs` jobs in all (0: no count limit). Unfinished jobs are never deleted.
struct RetentionPolicy {
  std::int64_t ttl_ms = 0;
  std::size_t max_jobs = 0;
};

// Thrown by create_job for an id already in use.
class DuplicateJobId : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Thrown by create_job when the job's request id is taken: the same submitter created a
// job under it that still exists. Carries that job, so the caller can tell a retry of the
// same request (equal fingerprints) from a different one.
class RequestIdTaken : public std::invalid_argument {
 public:
  explicit RequestIdTaken(JobRecord existing)
      : std::invalid_argument("request id '" + existing.request_id + "' is already job " +
                              existing.id),
        existing_(std::move(existing)) {}
  const JobRecord& existing() const { return existing_; }

 private:
  JobRecord existing_;
};

// Where jobs live: records, scenes and finished tiles, and the tile work between them
// (claims with leases, then completion) as store operations, so the scheduler never holds
// the only copy of anything. Every operation is atomic: a daemon killed at any instant
// leaves each job either before or after it. The embedded implementation is SQLite
// (SqliteJobStore); the interface is shaped so a shared database (PostgreSQL) can serve
// several daemons: claims name an owner and expire, and completion checks the job's state
// in the same transaction that stores the tile. Thread-safe.
class JobStore {
 public:
  virtual ~JobStore() = default;

  // Stores a new job (state kQueued) with its scene, and its request id when it has one.
  // Returns the record with its sequence. Throws DuplicateJobId when the id is taken, and
  // RequestIdTaken when the job's (submitter, request_id) names an existing job; both are
  // checked in the transaction that stores the job, so two concurrent submissions of one
  // request create one job.
  virtual JobRecord create_job(const JobRecord& job, const SceneSource& scene) = 0;
  virtual std::optional<JobRecord> find_job(std::string_view id) const = 0;
  // The job created by `submitter` (as it was at submission) under `request_id`, while it
  // exists.
  virtual std::optional<JobRecord> find_job_by_request(std::string_view submitter,
                                                       std::string_view request_id) const = 0;
  // Newest first.
  virtual std::vector<JobRecord> list_jobs(const JobQuery& query) const = 0;
  // Queued, running and paused jobs, oldest first: what a starting daemon resumes (the
  // paused ones stay paused).
  virtual std::vector<JobRecord> unfinished_jobs() const = 0;
  virtual std::optional<SceneSource> scene(std::string_view id) const = 0;
  // Queued, running and paused jobs of one submitter.
  virtual std::size_t unfinished_count(std::string_view submitter) const = 0;
  // Adds `prepare_ms` to the job's preparation time (any state); the record after, or
  // nothing for an unknown job.
  virtual std::optional<JobRecord> add_prepare_time(std::string_view id,
                                                    std::int64_t prepare_ms) = 0;
  // How many jobs are in each state (states without jobs are absent): /metrics.
  virtual std::map<JobState, std::size_t> count_by_state() const = 0;

  // State transitions. Each applies only to an unfinished job and returns the record after
  // it, or nothing when the job is finished or unknown.
  virtual std::optional<JobRecord> mark_running(std::string_view id, std::int64_t now_ms) = 0;
  // `state` is kCompleted, kFailed or kCancelled; `message` is the error or cancel reason.
  // Applies to paused jobs too.
  virtual std::optional<JobRecord> finish_job(std::string_view id, JobState state,
                                              const std::string& message, std::int64_t now_ms) = 0;

  // Job control. Each returns the record after the change, or nothing when the job is
  // unknown or not in a state the change applies to (the caller reads it to say why).
  // Queued or running -> paused.
  virtual std::optional<JobRecord> pause_job(std::string_view id) = 0;
  // Paused -> queued.
  virtual std::optional<JobRecord> resume_job(std::string_view id) = 0;
  // Failed or cancelled -> queued, keeping its tiles; clears the error, the finish time and
  // the tile failure counts.
  virtual std::optional<JobRecord> retry_job(std::string_view id) = 0;
  // Any state.
  virtual std::optional<JobRecord> update_job(std::string_view id, const JobUpdate& update) = 0;
  // Counts one failed attempt at a tile (render, encoding or storage threw) and returns how
  // many attempts at it have failed since the job was submitted or last retried. Kept in
  // the store, so a restart does not give a failing tile fresh attempts.
  virtual std::uint32_t record_tile_failure(std::string_view id, std::uint32_t index) = 0;

  // Tiles. A worker claims a tile before rendering it and commits it after; a claim held
  // by another live owner, or a tile already stored, is refused. A claim lapses at
  // `lease_until_ms` (an owner that died gives its tiles back by not renewing them).
  virtual bool claim_tile(std::string_view id, std::uint32_t index, std::string_view owner,
                          std::int64_t lease_until_ms, std::int64_t now_ms) = 0;
  virtual void release_tile(std::string_view id, std::uint32_t index, std::string_view owner) = 0;
  // Stores a rendered tile and adds its rays to the job, completing the job with its last
  // tile, in one transaction; releases the claim. A running or paused job takes the tile
  // (a paused job keeps the tiles that were in flight when it was paused).
  virtual TileCommitResult commit_tile(std::string_view id, std::uint32_t index,
                                       std::string_view owner, const std::vector<std::uint8_t>& exr,
                                       std::uint64_t rays, std::int64_t now_ms) = 0;
  // The same for one pass of a tile of a job with passes (job_passes.hpp: `index` is the
  // pass's store index): in the same transaction, `state` replaces the tile's accumulated
  // state, or, for its last pass (`last_pass`), the state is dropped. A duplicate or a job
  // not running changes no state.
  virtual TileCommitResult commit_tile_pass(std::string_view id, std::uint32_t index,
                                            std::string_view owner,
                                            const std::vector<std::uint8_t>& exr,
                                            std::uint64_t rays, std::int64_t now_ms,
                                            const TilePassState& state, bool last_pass) = 0;
  // The accumulated state of `tile` (grid index), when a pass of it is stored and its last
  // pass is not.
  virtual std::optional<TilePassState> tile_pass_state(std::string_view id,
                                                       std::uint32_t tile) const = 0;
  virtual std::vector<std::uint32_t> stored_tile_indices(std::string_view id) const = 0;
  // Tiles with ordinal > `after_ordinal`, in ordinal order, at most `limit`.
  virtual std::vector<StoredTile> tiles_after(std::string_view id, std::uint32_t after_ordinal,
                                              std::size_t limit) const = 0;
  // How many times each tile was committed (a re-rendered finished tile shows as 2): the
  // counter tests use to prove that no finished tile is rendered again. 0 when not stored.
  virtual std::uint32_t tile_commit_count(std::string_view id, std::uint32_t index) const = 0;

  // Deletes a finished job with its tiles (and its scene, unless another job shares it).
  // Returns false, deleting nothing, for an unfinished or unknown job.
  virtual bool delete_job(std::string_view id) = 0;
  // Applies `policy`; returns the ids deleted.
  virtual std::vector<std::string> apply_retention(const RetentionPolicy& policy,
                                                   std::int64_t now_ms) = 0;
};

}  // namespace tessera::server
