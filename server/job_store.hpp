#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "server/job.hpp"

namespace tessera::server {

// Where jobs are kept. In memory for now; the interface is what a persistent store will
// implement, so the service and scheduler never depend on how jobs are kept.
class JobStore {
 public:
  virtual ~JobStore() = default;

  // Adds a new job; throws std::invalid_argument if its id is already taken.
  virtual void add(std::shared_ptr<Job> job) = 0;
  // The job with `id`, or null.
  virtual std::shared_ptr<Job> find(std::string_view id) const = 0;
  // Every job, newest (most recently added) first.
  virtual std::vector<std::shared_ptr<Job>> list() const = 0;
};

class InMemoryJobStore final : public JobStore {
 public:
  void add(std::shared_ptr<Job> job) override;
  std::shared_ptr<Job> find(std::string_view id) const override;
  std::vector<std::shared_ptr<Job>> list() const override;

 private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Job>> in_order_;  // oldest first
  std::unordered_map<std::string, std::shared_ptr<Job>> by_id_;
};

}  // namespace tessera::server
