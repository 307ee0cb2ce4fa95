#include "server/job_store.hpp"

#include <stdexcept>

namespace tessera::server {

void InMemoryJobStore::add(std::shared_ptr<Job> job) {
  std::lock_guard lock(mutex_);
  const auto [it, inserted] = by_id_.emplace(job->id(), job);
  if (!inserted) throw std::invalid_argument("job id '" + job->id() + "' is already in use");
  in_order_.push_back(std::move(job));
}

std::shared_ptr<Job> InMemoryJobStore::find(std::string_view id) const {
  std::lock_guard lock(mutex_);
  const auto it = by_id_.find(std::string(id));
  return it == by_id_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<Job>> InMemoryJobStore::list() const {
  std::lock_guard lock(mutex_);
  return {in_order_.rbegin(), in_order_.rend()};
}

}  // namespace tessera::server
