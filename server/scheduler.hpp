#pragma once
#include <chrono>
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

// Reads a job's scene back from where it is kept (the daemon: the job store). Throws when
// the scene cannot be read or no longer converts.
using LoadSceneFn = std::function<SceneDescription(const Job&)>;

struct SchedulerOptions {
  unsigned threads = 1;
  // Builds a job's render-ready scene; replaceable so tests can make preparation fail.
  PrepareSceneFn prepare = default_prepare;
  // For jobs submitted without a scene in memory (every job the daemon runs, so a queued
  // job costs no scene memory and a resumed one takes the same path).
  LoadSceneFn load_scene;
  // Names this scheduler's tile claims in the store.
  std::string owner = "scheduler";
  // Called on the worker thread; for tests and instrumentation. Must not throw.
  std::function<void(const Job&)> on_job_started;
  // Called on the worker thread just before a claimed tile starts rendering.
  std::function<void(const Job&, const TileRect&)> on_tile_started;
  // `kept` is false when the job had finished (been cancelled) while the tile rendered.
  std::function<void(const Job&, const TileRect&, bool kept)> on_tile_rendered;
  // Called, under the scheduler's lock, when the scheduler lets go of a finished job.
  // Must be quick and must not call the scheduler.
  std::function<void(const Job&)> on_job_released;
};

// Runs jobs on a pool of worker threads. Each job's scene is prepared once (by whichever
// worker picks the job up first) and shared by all its tiles; the tiles of every running
// job are handed out in order of job priority (higher first, then submission order), so
// a lower-priority job only gets workers that the jobs above it cannot use. Tiles the store
// already holds (a job resumed after a restart) are not rendered again; every tile is
// claimed in the store before it is rendered and committed to it after. A tile being
// rendered checks its job's stop flag, so a cancel reaches it within a fraction of a
// second. Exceptions from preparing or rendering fail that job alone.
class Scheduler {
 public:
  explicit Scheduler(SchedulerOptions options);
  ~Scheduler();  // stop()
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Launches the worker threads. Jobs submitted before are queued and start now.
  void start();

  // Queues a job with its validated scene. The job's tile count must match the scene's
  // render settings. Returns false, leaving the job untouched, once stop() has begun.
  bool submit(std::shared_ptr<Job> job, SceneDescription scene);
  // Queues a job whose scene options.load_scene reads when the job is prepared.
  bool submit(std::shared_ptr<Job> job);

  // Call after cancelling a job from outside, so its remaining tiles are not handed out
  // and the scheduler forgets it.
  void job_changed();

  // Blocks until every submitted job has finished and no tile is in flight.
  void wait_idle();

  // Stops handing out work, gives the tiles in flight up to `grace` to finish (they are
  // stored), then makes the rest give up (they are discarded: a restart renders them
  // again), and joins the workers. Jobs are left as they are, queued or running, for a
  // restarted daemon to resume. Idempotent.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(0));

  unsigned threads() const { return options_.threads; }

 private:
  struct Entry;
  struct Task;

  void worker_loop();
  bool take_task_locked(Task& task);
  void prune_locked();
  void prepare(Entry& entry);
  void render(Entry& entry, const TileRect& rect);
  bool enqueue(std::shared_ptr<Entry> entry);

  SchedulerOptions options_;
  std::mutex mutex_;
  std::condition_variable work_available_;
  std::condition_variable idle_;
  std::vector<std::shared_ptr<Entry>> queue_;  // priority descending, then submission order
  std::uint64_t next_sequence_ = 0;
  unsigned in_flight_ = 0;  // tasks running on workers, over every entry
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace tessera::server
