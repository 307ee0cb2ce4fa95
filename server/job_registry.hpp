#pragma once
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>

#include "server/job.hpp"
#include "server/job_store.hpp"

namespace tessera::server {

class SubmitterQuotaExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The daemon's jobs: the store holds them all; this keeps a live Job object for each
// unfinished one (the scheduler and streams share it), so memory grows with the work in
// hand, not with history. A finished job is read from the store when asked for.
class JobRegistry {
 public:
  // `listener` (may be null) is told of every live job's changes, and of each job created.
  explicit JobRegistry(JobStore& store, JobListener* listener = nullptr)
      : store_(store), listener_(listener) {}

  JobStore& store() { return store_; }

  // Stores a new job with its scene and returns its live object. Throws DuplicateJobId,
  // RequestIdTaken when the record's request id names an existing job of its submitter
  // (checked before the cap), and SubmitterQuotaExceeded when the job's submitter already has
  // `max_unfinished_per_submitter` queued or running jobs (0: no limit).
  std::shared_ptr<Job> create(const JobRecord& record, const SceneSource& scene,
                              std::size_t max_unfinished_per_submitter = 0);
  // A job loaded from the store (resumed after a restart).
  std::shared_ptr<Job> adopt(const JobRecord& record);
  // The live job with `id`, or a snapshot of a finished one from the store; null if unknown.
  std::shared_ptr<Job> find(std::string_view id);
  // Retries a failed or cancelled job (Job::retry) and makes it live again. The job is null
  // when unknown; `result` says what happened.
  std::shared_ptr<Job> retry(std::string_view id, ControlResult& result);
  // Drops the live object of a finished job (the store keeps it).
  void forget(const std::string& id);
  std::size_t live_count() const;

 private:
  JobStore& store_;
  JobListener* const listener_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<Job>> live_;
};

}  // namespace tessera::server
