#pragma once
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/job.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera::server {

using PrepareSceneFn = std::function<std::shared_ptr<const PreparedScene>(const SceneDescription&)>;

inline std::shared_ptr<const PreparedScene> default_prepare(const SceneDescription& scene) {
  return PreparedScene::build(scene);
}

struct SchedulerOptions {
  unsigned threads = 1;
  // Builds a job's render-ready scene; replaceable so tests can make preparation fail.
  PrepareSceneFn prepare = default_prepare;
  // Called on the worker thread; for tests and instrumentation. Must not throw.
  std::function<void(const Job&)> on_job_started;
  // `kept` is false when the job had finished (been cancelled) while the tile rendered.
  std::function<void(const Job&, const TileRect&, bool kept)> on_tile_rendered;
};

// Runs jobs on a pool of worker threads. Each job's scene is prepared once (by whichever
// worker picks the job up first) and shared by all its tiles; the tiles of every running
// job are handed out in order of job priority (higher first, then submission order), so
// a lower-priority job only gets workers that the jobs above it cannot use. Exceptions
// from preparing or rendering fail that job alone.
class Scheduler {
 public:
  explicit Scheduler(SchedulerOptions options);
  ~Scheduler();  // stop("daemon shutting down")
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Launches the worker threads. Jobs submitted before are queued and start now.
  void start();

  // Queues a job with its validated scene. The job's tile count must match the scene's
  // render settings. Returns false, leaving the job untouched, once stop() has begun.
  bool submit(std::shared_ptr<Job> job, SceneDescription scene);

  // Call after cancelling a job from outside, so its remaining tiles are not handed out
  // and the scheduler forgets it.
  void job_changed();

  // Blocks until every submitted job has finished and no tile is in flight.
  void wait_idle();

  // Cancels every unfinished job with `reason`, lets tiles in flight finish (their
  // results are dropped) and joins the workers. Idempotent.
  void stop(const std::string& reason);

  unsigned threads() const { return options_.threads; }

 private:
  struct Entry;
  struct Task;

  void worker_loop();
  bool take_task_locked(Task& task);
  void prune_locked();
  void prepare(Entry& entry);
  void render(Entry& entry, const TileRect& rect);

  SchedulerOptions options_;
  std::mutex mutex_;
  std::condition_variable work_available_;
  std::condition_variable idle_;
  std::vector<std::shared_ptr<Entry>> queue_;  // priority descending, then submission order
  std::uint64_t next_sequence_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace tessera::server
