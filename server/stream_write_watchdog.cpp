#include "server/stream_write_watchdog.hpp"

#include <grpcpp/server_context.h>

namespace tessera::server {

StreamWriteWatchdog::StreamWriteWatchdog(std::chrono::milliseconds timeout)
    : timeout_(timeout), thread_([this] { run(); }) {}

StreamWriteWatchdog::~StreamWriteWatchdog() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

StreamWriteWatchdog::Outcome StreamWriteWatchdog::write(grpc::ServerContext& context,
                                                        const std::function<bool()>& write) {
  std::uint64_t id = 0;
  {
    std::lock_guard lock(mutex_);
    id = next_id_++;
    pending_[id] = Pending{std::chrono::steady_clock::now() + timeout_, &context, false};
  }
  changed_.notify_all();
  const bool written = write();
  // Unregistered under the lock before returning, so the watchdog never touches a context
  // whose call has ended.
  std::lock_guard lock(mutex_);
  const auto it = pending_.find(id);
  const bool expired = it->second.expired;
  pending_.erase(it);
  if (expired) return Outcome::kTimedOut;
  return written ? Outcome::kWritten : Outcome::kFailed;
}

std::uint64_t StreamWriteWatchdog::timeouts() const {
  std::lock_guard lock(mutex_);
  return timeouts_;
}

void StreamWriteWatchdog::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    // Every write has the same timeout, so the oldest registered has the earliest deadline
    // among those not yet expired.
    auto next = pending_.end();
    for (auto it = pending_.begin(); it != pending_.end(); ++it)
      if (!it->second.expired) {
        next = it;
        break;
      }
    if (next == pending_.end()) {
      changed_.wait(lock);
      continue;
    }
    // A copy: the wait releases the lock, and the write may then erase its entry, which
    // wait_until would otherwise still read (AddressSanitizer caught that).
    const std::chrono::steady_clock::time_point deadline = next->second.deadline;
    if (std::chrono::steady_clock::now() < deadline) {
      changed_.wait_until(lock, deadline);
      continue;
    }
    next->second.expired = true;
    ++timeouts_;
    next->second.context->TryCancel();
  }
}

}  // namespace tessera::server
