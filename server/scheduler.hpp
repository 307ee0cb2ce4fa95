#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "server/job.hpp"
#include "server/tile_device.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera::server {

class DaemonMetrics;

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
  // A job whose scene preparation takes longer fails (0: no limit). The build itself
  // cannot be interrupted (the BVH build is one TBB parallel step), so the job fails, and
  // its worker is free, when the build returns; the budgets checked at submission
  // (primitives, memory estimate) are what bound how long that can be.
  std::chrono::milliseconds prepare_timeout{0};
  // Names this scheduler's tile claims in the store.
  std::string owner = "scheduler";
  // Fairness across priorities: once a job has been handed `long_job_tiles` tiles, every
  // `yield_every`-th tile it would get goes to the best job of a lower priority instead
  // (0: strict priority).
  std::uint32_t long_job_tiles = 32;
  std::uint32_t yield_every = 8;
  // Called on the worker thread; for tests and instrumentation. Must not throw.
  std::function<void(const Job&)> on_job_started;
  // Called on the worker thread just before a claimed tile starts rendering. May throw:
  // the attempt then fails as a render that threw does (how tests inject tile failures
  // without touching the render path).
  std::function<void(const Job&, const TileRect&)> on_tile_started;
  // Failed attempts at one tile (render, encoding or storage threw) that are retried
  // before its job fails; the count is kept in the store.
  std::uint32_t tile_retries = 2;
  // `kept` is false when the job had finished (been cancelled) while the tile rendered.
  std::function<void(const Job&, const TileRect&, bool kept)> on_tile_rendered;
  // Called, under the scheduler's lock, when the scheduler lets go of a finished job.
  // Must be quick and must not call the scheduler.
  std::function<void(const Job&)> on_job_released;
  // Counters for /metrics (tiles, samples, rays, trace and preparation time, queue
  // latency); null: not counted. Must outlive the scheduler.
  DaemonMetrics* metrics = nullptr;
  // Devices besides the `threads` CPU workers (GPUs), one worker thread each. A device
  // takes tiles of the jobs it accepts (TileDevice::accepts) that render in one pass without
  // AOVs, unless the job asks for the CPU (render.device); a job that asks for a GPU renders on
  // the devices alone, and fails when none accepts it. Every other job's tiles, and job
  // preparation, stay with the CPU workers.
  std::vector<std::shared_ptr<TileDevice>> devices;
};

// What the scheduler holds now (for /metrics).
struct SchedulerLoad {
  std::size_t jobs_with_work = 0;  // runnable jobs with tiles not yet handed out (or unprepared)
  std::size_t pending_tiles = 0;   // tiles of prepared jobs not yet handed out
  unsigned in_flight = 0;          // tasks running on workers
};

// Runs jobs on a pool of worker threads. Each job's scene is prepared once (by whichever
// worker picks the job up first) and shared by all its tiles.
//
// Which tile next: the highest priority with work wins, and within it the submitter served
// least recently (round-robin by submitter, then submission order within a submitter), so
// one client's thousand jobs cannot starve another's one at the same priority. Priority
// stays nearly strict but not absolute: a long job (options.long_job_tiles handed out)
// yields every options.yield_every-th tile to the best lower-priority job, so a short
// low-priority job advances at a known share of the workers instead of waiting for days.
// Round-robin by submitter rather than weighted fair share: no weights to configure,
// nothing to tune, and the share each submitter gets is obvious from the queue. Tiles the store
// already holds (a job resumed after a restart) are not rendered again; every tile is
// claimed in the store before it is rendered and committed to it after. A job with
// progressive passes hands out pass 1 of every tile, then pass 2, and so on; a tile's next
// pass waits while its previous one renders. A tile being
// rendered checks its job's stop flag, so a cancel reaches it within a fraction of a
// second. Exceptions from preparing or rendering fail that job alone.
// One unit of work: a pass of a tile (the tile itself for a one-pass job), with its store
// index (job_passes.hpp).
struct TileWork {
  TileRect rect;
  std::uint32_t pass = 1;
  std::uint32_t unit = 0;
};

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

  // Call after cancelling, pausing or re-prioritising a job from outside, so a finished or
  // paused job's remaining tiles are not handed out (the scheduler forgets it once its
  // tiles in flight return) and the queue follows the new priorities.
  void job_changed();

  // Queues again a job that was paused and resumed, or failed or cancelled and retried:
  // it is prepared afresh and renders only the tiles the store lacks. An entry of its
  // earlier run with tiles still in flight is retired, and the new one queued once they
  // have returned (so no tile renders twice). Returns false once stop() has begun.
  bool requeue(std::shared_ptr<Job> job);

  // Blocks until every submitted job has finished and no tile is in flight.
  void wait_idle();

  // Stops handing out work, gives the tiles in flight up to `grace` to finish (they are
  // stored), then makes the rest give up (they are discarded: a restart renders them
  // again), and joins the workers. Jobs are left as they are, queued or running, for a
  // restarted daemon to resume. Idempotent.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(0));

  unsigned threads() const { return options_.threads; }
  SchedulerLoad load();

 private:
  struct Entry;
  struct Task;

  static bool queue_order(const std::shared_ptr<Entry>& a, const std::shared_ptr<Entry>& b);
  // `device`: the worker's index in options_.devices, or kCpuWorker.
  static constexpr std::size_t kCpuWorker = static_cast<std::size_t>(-1);
  void worker_loop(std::size_t device);
  bool take_task_locked(Task& task, std::size_t device);
  void prune_locked();
  void prepare(Entry& entry);
  // Per device, whether it takes `scene`'s tiles (render.device, one pass,
  // TileDevice::accepts). Throws for a job that asks for a GPU when none takes it.
  std::vector<bool> devices_for(const Job& job, const PreparedScene& scene) const;
  struct Attempt;
  // Claims, renders and stores `works` (one, or a device's batch), `device` as for
  // worker_loop.
  void render(Entry& entry, std::span<const TileWork> works, std::size_t device);
  // The one-pass tiles of `attempts` that were claimed: rendered together, then stored.
  void render_and_store(Entry& entry, std::vector<Attempt>& attempts, std::size_t device,
                        std::uint64_t run);
  // Releases a claim left over, hands a failed tile back (tile_failed), counts a stored one
  // and logs the job's completion when it was the last.
  void finish(Entry& entry, const Attempt& attempt, std::uint64_t run);
  // The one-pass render of `rects` into `passes`: on options_.devices[device] unless it is
  // kCpuWorker, all at once, falling back to the CPU (logged) when that fails; counted
  // (count_rendered).
  void render_whole_tiles(Entry& entry, std::span<const TileRect> rects, std::size_t device,
                          std::span<TilePasses> passes, std::span<TileStats> stats);
  // A tile (pass) rendered by `worker` (0: the CPU, 1 + d: device d), for the job's
  // completion log and options_.metrics.
  void count_rendered(Entry& entry, std::size_t worker, std::size_t tiles = 1) const;
  // "cpu 30, gpu0 NVIDIA H100 80GB HBM3 18 (2 failed on a device and went to the CPU)".
  std::string tile_split(const Entry& entry) const;
  // A pass of a tile of a job with passes: continues the tile's stored state and stores the
  // new one with the tile's image after the pass. Nothing when the pass was cut short (the
  // claim is then still held).
  std::optional<AddTileResult> render_pass(Entry& entry, const TileWork& work);
  // A failed attempt at `work`: hands it out again, or fails the job once it has failed
  // more than options_.tile_retries times.
  void tile_failed(Entry& entry, const TileWork& work, const std::string& reason);
  bool enqueue(std::shared_ptr<Entry> entry);
  // Adds a render call's rays and seconds to options_.metrics.
  void count_trace(const TileStats& stats, std::chrono::steady_clock::time_point start) const;
  // The samples a unit of work asks for: its pixels times its pass's samples.
  static std::uint64_t tile_samples(const PreparedScene& scene, const TileWork& work);

  SchedulerOptions options_;
  std::mutex mutex_;
  std::condition_variable work_available_;
  std::condition_variable idle_;
  std::vector<std::shared_ptr<Entry>> queue_;  // priority descending, then submission order
  std::uint64_t next_sequence_ = 0;
  unsigned in_flight_ = 0;  // tasks running on workers, over every entry
  // Round-robin state: when each submitter with queued work was last served, and how many
  // tiles have been handed out in all (for yielding).
  std::unordered_map<std::string, std::uint64_t> last_served_;
  std::uint64_t served_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace tessera::server
