#include "server/metrics.hpp"

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <fstream>

namespace tessera::server {
namespace {

// Scene preparation and job latencies span milliseconds (a Cornell box) to hours (a
// large job waiting behind others).
const std::vector<double> kPrepareBounds = {0.001, 0.01, 0.1, 0.5, 1, 2.5, 5, 10, 30, 60, 300};
const std::vector<double> kJobBounds = {0.1, 1, 5, 15, 60, 300, 900, 3600, 4 * 3600, 24 * 3600};

constexpr JobState kFinishedStates[] = {JobState::kCompleted, JobState::kFailed,
                                        JobState::kCancelled};
constexpr JobState kAllStates[] = {JobState::kQueued,    JobState::kRunning, JobState::kPaused,
                                   JobState::kCompleted, JobState::kFailed,  JobState::kCancelled};

std::string number(double value) {
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  // The shortest text that reads back as the same double.
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

void header(std::string& out, const char* name, const char* type, const char* help) {
  out.append("# HELP ").append(name).append(" ").append(help).append("\n");
  out.append("# TYPE ").append(name).append(" ").append(type).append("\n");
}

// A label value as the exposition format quotes it: backslash, double quote and newline
// escaped (device names come from the driver).
std::string label_value(const std::string& value) {
  std::string escaped;
  for (const char c : value) {
    if (c == '\\' || c == '"') escaped.push_back('\\');
    if (c == '\n') {
      escaped.append("\\n");
      continue;
    }
    escaped.push_back(c);
  }
  return escaped;
}

void sample(std::string& out, const std::string& name, const std::string& labels, double value) {
  out.append(name);
  if (!labels.empty()) out.append("{").append(labels).append("}");
  out.append(" ").append(number(value)).append("\n");
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds)), counts_(bounds_.size() + 1) {}

void Histogram::observe(double value) {
  std::size_t bucket = 0;
  while (bucket < bounds_.size() && value > bounds_[bucket]) ++bucket;
  counts_[bucket].fetch_add(1, std::memory_order_relaxed);
  sum_.fetch_add(value, std::memory_order_relaxed);
}

void Histogram::write(std::string& out, const std::string& name, const std::string& labels) const {
  const std::string prefix = labels.empty() ? "" : labels + ",";
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i <= bounds_.size(); ++i) {
    cumulative += counts_[i].load(std::memory_order_relaxed);
    const std::string le = i < bounds_.size() ? number(bounds_[i]) : "+Inf";
    sample(out, name + "_bucket", prefix + "le=\"" + le + "\"", static_cast<double>(cumulative));
  }
  sample(out, name + "_sum", labels, sum_.load(std::memory_order_relaxed));
  sample(out, name + "_count", labels, static_cast<double>(cumulative));
}

DaemonMetrics::DaemonMetrics()
    : prepare_seconds_(kPrepareBounds),
      queue_seconds_(kJobBounds),
      run_seconds_{Histogram(kJobBounds), Histogram(kJobBounds), Histogram(kJobBounds)} {}

void DaemonMetrics::tile_traced(std::uint64_t rays, double seconds) {
  rays_.fetch_add(rays, std::memory_order_relaxed);
  trace_seconds_.fetch_add(seconds, std::memory_order_relaxed);
}

void DaemonMetrics::tile_stored(std::uint64_t samples) {
  tiles_.fetch_add(1, std::memory_order_relaxed);
  samples_.fetch_add(samples, std::memory_order_relaxed);
}

void DaemonMetrics::name_tile_workers(std::vector<std::string> names) {
  if (names.size() > kMaxTileWorkers) names.resize(kMaxTileWorkers);
  worker_names_ = std::move(names);
}

void DaemonMetrics::tile_rendered_by(std::size_t worker, std::uint64_t tiles) {
  if (worker < kMaxTileWorkers) rendered_by_[worker].fetch_add(tiles, std::memory_order_relaxed);
}

void DaemonMetrics::tile_fell_back(std::size_t device, std::uint64_t tiles) {
  if (device < kMaxTileWorkers) fell_back_[device].fetch_add(tiles, std::memory_order_relaxed);
}

std::uint64_t DaemonMetrics::tiles_rendered_by(std::size_t worker) const {
  return worker < kMaxTileWorkers ? rendered_by_[worker].load(std::memory_order_relaxed) : 0;
}

std::uint64_t DaemonMetrics::tiles_fallen_back(std::size_t device) const {
  return device < kMaxTileWorkers ? fell_back_[device].load(std::memory_order_relaxed) : 0;
}

void DaemonMetrics::scene_prepared(double seconds) {
  prepare_seconds_.observe(seconds);
}

void DaemonMetrics::job_started(double queued_seconds) {
  queue_seconds_.observe(queued_seconds);
}

void DaemonMetrics::job_finished(JobState state, double run_seconds) {
  for (std::size_t i = 0; i < std::size(kFinishedStates); ++i)
    if (kFinishedStates[i] == state) run_seconds_[i].observe(run_seconds);
}

std::string DaemonMetrics::exposition(const MetricsSnapshot& s) const {
  std::string out;
  out.reserve(8192);
  header(out, "tessera_build_info", "gauge", "Always 1; the version is a label.");
  sample(out, "tessera_build_info", std::string("version=\"") + TESSERA_VERSION + "\"", 1);

  header(out, "tessera_jobs", "gauge", "Jobs in the store, by state.");
  for (const JobState state : kAllStates) {
    const auto it = s.jobs_by_state.find(state);
    sample(out, "tessera_jobs", std::string("state=\"") + to_string(state) + "\"",
           static_cast<double>(it == s.jobs_by_state.end() ? 0 : it->second));
  }
  header(out, "tessera_queue_depth", "gauge",
         "Queued and running jobs whose tiles are not all handed out to workers yet.");
  sample(out, "tessera_queue_depth", "", static_cast<double>(s.queued_jobs));
  header(out, "tessera_queue_tiles", "gauge",
         "Tiles (tile passes) of prepared jobs waiting for a worker.");
  sample(out, "tessera_queue_tiles", "", static_cast<double>(s.pending_tiles));
  header(out, "tessera_tiles_in_flight", "gauge", "Tasks (tiles, scene preparations) on workers.");
  sample(out, "tessera_tiles_in_flight", "", s.tiles_in_flight);
  header(out, "tessera_render_threads", "gauge", "Render worker threads.");
  sample(out, "tessera_render_threads", "", s.render_threads);

  header(out, "tessera_tiles_rendered_total", "counter",
         "Tiles (with passes: tile passes) rendered and stored.");
  sample(out, "tessera_tiles_rendered_total", "",
         static_cast<double>(tiles_.load(std::memory_order_relaxed)));
  if (!worker_names_.empty()) {
    header(out, "tessera_tiles_rendered_by_device_total", "counter",
           "Tiles (tile passes) rendered, kept or not, by the worker that rendered them: cpu "
           "(the CPU threads) or a GPU.");
    for (std::size_t w = 0; w < worker_names_.size(); ++w)
      sample(out, "tessera_tiles_rendered_by_device_total",
             "device=\"" + label_value(worker_names_[w]) + "\"",
             static_cast<double>(tiles_rendered_by(w)));
    if (worker_names_.size() > 1) {
      header(out, "tessera_device_fallbacks_total", "counter",
             "Tiles that failed on a GPU and were rendered on the CPU instead.");
      for (std::size_t d = 0; d + 1 < worker_names_.size(); ++d)
        sample(out, "tessera_device_fallbacks_total",
               "device=\"" + label_value(worker_names_[d + 1]) + "\"",
               static_cast<double>(tiles_fallen_back(d)));
    }
  }
  header(out, "tessera_samples_rendered_total", "counter",
         "Pixel samples of the stored tiles (pixels times the samples each asked for).");
  sample(out, "tessera_samples_rendered_total", "",
         static_cast<double>(samples_.load(std::memory_order_relaxed)));
  header(out, "tessera_rays_traced_total", "counter", "Rays traced by the render workers.");
  sample(out, "tessera_rays_traced_total", "",
         static_cast<double>(rays_.load(std::memory_order_relaxed)));
  header(out, "tessera_trace_seconds_total", "counter",
         "Worker seconds spent tracing tiles (scene preparation, encoding and storing "
         "excluded); rate(tessera_rays_traced_total) / rate(tessera_trace_seconds_total) is "
         "rays per second per worker.");
  sample(out, "tessera_trace_seconds_total", "", trace_seconds_.load(std::memory_order_relaxed));

  header(out, "tessera_scene_prepare_seconds", "histogram",
         "Time to prepare a job's scene (conversion, BVH build) before its first tile.");
  prepare_seconds_.write(out, "tessera_scene_prepare_seconds", "");
  header(out, "tessera_job_queue_seconds", "histogram",
         "Time from a job's submission to its first start on a worker.");
  queue_seconds_.write(out, "tessera_job_queue_seconds", "");
  header(out, "tessera_job_run_seconds", "histogram",
         "Time from a job's start to its end, by the state it ended in.");
  for (std::size_t i = 0; i < std::size(kFinishedStates); ++i)
    run_seconds_[i].write(out, "tessera_job_run_seconds",
                          std::string("state=\"") + to_string(kFinishedStates[i]) + "\"");

  header(out, "tessera_store_size_bytes", "gauge",
         "Size of the job store's files (database and write-ahead log).");
  sample(out, "tessera_store_size_bytes", "", static_cast<double>(s.store_bytes));
  header(out, "tessera_process_resident_memory_bytes", "gauge",
         "Resident memory of the tesserad process.");
  sample(out, "tessera_process_resident_memory_bytes", "", static_cast<double>(s.resident_bytes));
  return out;
}

void MetricsJobListener::job_changed(const JobRecord& job) {
  if (is_finished(job.state) && job.started_unix_ms > 0 && job.finished_unix_ms > 0)
    metrics_.job_finished(job.state,
                          static_cast<double>(job.finished_unix_ms - job.started_unix_ms) / 1000.0);
  if (next_) next_->job_changed(job);
}

std::uint64_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t size = 0;
  std::uint64_t resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

}  // namespace tessera::server
