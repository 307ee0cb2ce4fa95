#include "server/job_registry.hpp"

namespace tessera::server {

std::shared_ptr<Job> JobRegistry::create(const JobRecord& record, const SceneSource& scene,
                                         std::size_t max_unfinished_per_submitter) {
  // Under the lock, so find() never sees a job in the store that is not yet live here and
  // hands out a second, unshared object for it, and two submissions cannot both take the
  // last place under the cap.
  std::lock_guard lock(mutex_);
  // A retry of a request that created a job is answered with that job even when the
  // submitter is at its cap: it asks for nothing new. (The store checks again as it stores.)
  if (!record.request_id.empty()) {
    if (auto existing = store_.find_job_by_request(record.submitter, record.request_id))
      throw RequestIdTaken(std::move(*existing));
  }
  if (max_unfinished_per_submitter > 0) {
    const std::size_t unfinished = store_.unfinished_count(record.submitter);
    if (unfinished >= max_unfinished_per_submitter)
      throw SubmitterQuotaExceeded("submitter already has " + std::to_string(unfinished) +
                                   " queued or running jobs, the most this daemon accepts "
                                   "(max_jobs_per_submitter)");
  }
  auto job = std::make_shared<Job>(store_, store_.create_job(record, scene), listener_);
  live_.emplace(job->id(), job);
  if (listener_) listener_->job_changed(job->record());
  return job;
}

std::shared_ptr<Job> JobRegistry::adopt(const JobRecord& record) {
  std::lock_guard lock(mutex_);
  auto job = std::make_shared<Job>(store_, record, listener_);
  live_[job->id()] = job;
  return job;
}

std::shared_ptr<Job> JobRegistry::find(std::string_view id) {
  std::lock_guard lock(mutex_);
  if (const auto it = live_.find(std::string(id)); it != live_.end()) return it->second;
  auto record = store_.find_job(id);
  if (!record) return nullptr;
  return std::make_shared<Job>(store_, std::move(*record), listener_);
}

std::shared_ptr<Job> JobRegistry::retry(std::string_view id, ControlResult& result) {
  // Under the lock, so the job cannot be forgotten between its retry and going live.
  std::lock_guard lock(mutex_);
  std::shared_ptr<Job> job;
  if (const auto it = live_.find(std::string(id)); it != live_.end()) {
    job = it->second;
  } else {
    auto record = store_.find_job(id);
    if (!record) return nullptr;
    job = std::make_shared<Job>(store_, std::move(*record), listener_);
  }
  result = job->retry();
  if (result == ControlResult::kDone) live_[job->id()] = job;
  return job;
}

void JobRegistry::forget(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = live_.find(id);
  if (it != live_.end() && it->second->finished()) live_.erase(it);
}

std::size_t JobRegistry::live_count() const {
  std::lock_guard lock(mutex_);
  return live_.size();
}

}  // namespace tessera::server
