#pragma once
// The daemon's Prometheus metrics: counters and histograms the render path updates with
// relaxed atomics (once per tile or per job, never per ray), and the text exposition
// format a scrape of /metrics returns (metrics_http.hpp serves it).
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <unordered_set>
#include <vector>

#include "server/job.hpp"

namespace tessera::server {

// A histogram with fixed upper bounds (seconds), safe to observe from any thread.
class Histogram {
 public:
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
  // Appends the _bucket, _sum and _count lines; `labels` is "" or `key="value"`.
  void write(std::string& out, const std::string& name, const std::string& labels) const;

 private:
  std::vector<double> bounds_;
  std::vector<std::atomic<std::uint64_t>> counts_;  // per bucket, the last one is +Inf
  std::atomic<double> sum_{0.0};
};

// What a scrape reads at the time of the scrape rather than counting as it goes.
struct MetricsSnapshot {
  std::map<JobState, std::size_t> jobs_by_state;
  std::size_t queued_jobs = 0;    // jobs the scheduler holds that still have tiles to hand out
  std::size_t pending_tiles = 0;  // tiles of prepared jobs not yet handed out
  unsigned tiles_in_flight = 0;
  unsigned render_threads = 0;
  std::uint64_t store_bytes = 0;
  std::uint64_t resident_bytes = 0;
};

// The CPU threads and up to 64 devices.
inline constexpr std::size_t kMaxTileWorkers = 65;

class DaemonMetrics {
 public:
  DaemonMetrics();

  // A tile (or a pass of a tile) was rendered: its rays and the worker's seconds spent
  // tracing it (the render call alone: no preparation, encoding or storing). Counted
  // whether or not the tile was kept, since the rays were traced.
  void tile_traced(std::uint64_t rays, double seconds);
  // A rendered tile (or pass) was stored, with the samples it asked for.
  void tile_stored(std::uint64_t samples);
  // The workers that render tiles, named for the exposition: "cpu" (the CPU threads
  // together) first, then each device as TileDevice::name gives it. At most
  // kMaxTileWorkers; the scheduler names them when it is built.
  void name_tile_workers(std::vector<std::string> names);
  // A tile (or a pass of one) rendered by worker `worker` (0: the CPU threads, 1 + d:
  // device d), whether or not it was kept; and one that failed on device d and was
  // rendered on the CPU instead.
  void tile_rendered_by(std::size_t worker, std::uint64_t tiles = 1);
  void tile_fell_back(std::size_t device, std::uint64_t tiles = 1);
  std::uint64_t tiles_rendered_by(std::size_t worker) const;
  std::uint64_t tiles_fallen_back(std::size_t device) const;
  void scene_prepared(double seconds);
  // A job started for the first time, `seconds` after it was submitted.
  void job_started(double queued_seconds);
  // A job finished in `state`, `seconds` after it started.
  void job_finished(JobState state, double run_seconds);

  // The text exposition format (version 0.0.4).
  std::string exposition(const MetricsSnapshot& snapshot) const;

  std::uint64_t rays_traced() const { return rays_.load(std::memory_order_relaxed); }
  std::uint64_t tiles_stored() const { return tiles_.load(std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> tiles_{0};
  std::vector<std::string> worker_names_;  // set before any tile renders
  std::array<std::atomic<std::uint64_t>, kMaxTileWorkers> rendered_by_{};
  std::array<std::atomic<std::uint64_t>, kMaxTileWorkers> fell_back_{};
  std::atomic<std::uint64_t> samples_{0};
  std::atomic<std::uint64_t> rays_{0};
  std::atomic<double> trace_seconds_{0.0};
  Histogram prepare_seconds_;
  Histogram queue_seconds_;
  std::array<Histogram, 3> run_seconds_;  // completed, failed, cancelled
};

// Observes when jobs finish (from the job's own record), then passes every change on to
// `next` (the WatchJobs hub).
class MetricsJobListener final : public JobListener {
 public:
  MetricsJobListener(DaemonMetrics& metrics, JobListener* next) : metrics_(metrics), next_(next) {}
  void job_changed(const JobRecord& job) override;

 private:
  DaemonMetrics& metrics_;
  JobListener* next_;
};

// This process's resident memory (/proc/self/statm), 0 when unreadable.
std::uint64_t resident_memory_bytes();

}  // namespace tessera::server
