#include "server/job_watch.hpp"

#include <algorithm>

namespace tessera::server {

bool WatchFilter::matches(const JobRecord& job) const {
  if (!job_id.empty() && job.id != job_id) return false;
  if (!submitter.empty() && job.submitter != submitter) return false;
  if (label_key) {
    const auto it = job.labels.find(*label_key);
    if (it == job.labels.end()) return false;
    if (label_value && it->second != *label_value) return false;
  }
  return true;
}

std::optional<JobChange> JobWatchHub::Watcher::next(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return !events_.empty() || dropped_ != WatchDrop::kNone; });
  if (dropped_ != WatchDrop::kNone || events_.empty()) return std::nullopt;
  JobChange change = std::move(events_.front());
  events_.pop_front();
  return change;
}

WatchDrop JobWatchHub::Watcher::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

void JobWatchHub::Watcher::begin_write() {
  std::lock_guard lock(mutex_);
  write_started_ = std::chrono::steady_clock::now();
}

void JobWatchHub::Watcher::end_write() {
  std::lock_guard lock(mutex_);
  write_started_.reset();
}

JobWatchHub::JobWatchHub(Options options) : options_(options) {
  watchdog_ = std::thread([this] { watchdog_loop(); });
}

JobWatchHub::~JobWatchHub() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_cv_.notify_all();
  watchdog_.join();
}

void JobWatchHub::drop(Watcher& watcher, WatchDrop why) {
  if (watcher.dropped_ != WatchDrop::kNone) return;
  watcher.dropped_ = why;
  watcher.events_.clear();
  watcher.ready_.notify_all();
  if (watcher.cancel_) watcher.cancel_();
}

std::shared_ptr<JobWatchHub::Watcher> JobWatchHub::subscribe(
    WatchFilter filter, const std::function<std::vector<JobRecord>()>& snapshot,
    std::function<void()> cancel) {
  auto watcher = std::make_shared<Watcher>();
  watcher->filter_ = std::move(filter);
  watcher->cancel_ = std::move(cancel);
  // Publishers take this lock after writing the store, so every change is either in the
  // snapshot read below or published to this watcher after it.
  std::lock_guard lock(mutex_);
  if (snapshot)
    for (JobRecord& job : snapshot())
      if (watcher->filter_.matches(job))
        watcher->events_.push_back(JobChange{std::move(job), false, true});
  watcher->capacity_ = watcher->events_.size() + options_.buffer_events;
  watchers_.push_back(watcher);
  return watcher;
}

void JobWatchHub::unsubscribe(const std::shared_ptr<Watcher>& watcher) {
  std::lock_guard lock(mutex_);
  std::erase(watchers_, watcher);
}

void JobWatchHub::job_changed(const JobRecord& job) {
  publish(JobChange{job, false, false});
}

void JobWatchHub::job_deleted(const JobRecord& job) {
  publish(JobChange{job, true, false});
}

void JobWatchHub::publish(const JobChange& change) {
  std::lock_guard lock(mutex_);
  for (const auto& watcher : watchers_) {
    if (!watcher->filter_.matches(change.job)) continue;
    std::lock_guard watcher_lock(watcher->mutex_);
    if (watcher->dropped_ != WatchDrop::kNone) continue;
    // Never wait for a slow watcher: it would stall the worker publishing.
    if (watcher->events_.size() >= watcher->capacity_) {
      drop(*watcher, WatchDrop::kBufferFull);
      continue;
    }
    watcher->events_.push_back(change);
    watcher->ready_.notify_one();
  }
}

std::size_t JobWatchHub::watcher_count() const {
  std::lock_guard lock(mutex_);
  return watchers_.size();
}

void JobWatchHub::watchdog_loop() {
  const auto period = std::clamp<std::chrono::milliseconds>(
      options_.write_timeout / 4, std::chrono::milliseconds(5), std::chrono::milliseconds(1000));
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    stop_cv_.wait_for(lock, period);
    const auto now = std::chrono::steady_clock::now();
    for (const auto& watcher : watchers_) {
      std::lock_guard watcher_lock(watcher->mutex_);
      if (watcher->write_started_ && now - *watcher->write_started_ > options_.write_timeout)
        drop(*watcher, WatchDrop::kWriteTimeout);
    }
  }
}

}  // namespace tessera::server
