#include "server/scheduler.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

#include "tessera/image/exr.hpp"
#include "tessera/render/output_channels.hpp"

namespace tessera::server {

// A job as the scheduler sees it. Guarded by Scheduler::mutex_, except `scene`, which only
// the one worker that set `preparing` touches.
struct Scheduler::Entry {
  std::shared_ptr<Job> job;
  std::uint64_t sequence = 0;
  std::unique_ptr<SceneDescription> scene;  // released once prepared
  std::shared_ptr<const PreparedScene> prepared;
  std::vector<TileRect> tiles;
  std::size_t next_tile = 0;  // tiles before it have been handed out
  bool preparing = false;
  unsigned in_flight = 0;  // tasks of this entry running on workers
};

struct Scheduler::Task {
  std::shared_ptr<Entry> entry;
  bool prepare = false;
  TileRect tile;
};

Scheduler::Scheduler(SchedulerOptions options) : options_(std::move(options)) {
  if (options_.threads == 0) throw std::invalid_argument("scheduler needs at least one thread");
  if (!options_.prepare) options_.prepare = default_prepare;
}

Scheduler::~Scheduler() {
  stop("daemon shutting down");
}

void Scheduler::start() {
  std::lock_guard lock(mutex_);
  if (stopping_ || !workers_.empty()) return;
  workers_.reserve(options_.threads);
  for (unsigned i = 0; i < options_.threads; ++i) workers_.emplace_back([this] { worker_loop(); });
}

bool Scheduler::submit(std::shared_ptr<Job> job, SceneDescription scene) {
  auto entry = std::make_shared<Entry>();
  const auto& r = scene.render;
  entry->tiles = make_tiles(r.width, r.height, r.tile_size);
  if (entry->tiles.size() != job->info().progress.tiles_total)
    throw std::logic_error("job " + job->id() + " has a tile count that does not match its scene");
  entry->job = std::move(job);
  entry->scene = std::make_unique<SceneDescription>(std::move(scene));
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    entry->sequence = next_sequence_++;
    const auto before = [](const std::shared_ptr<Entry>& a, const std::shared_ptr<Entry>& b) {
      if (a->job->priority() != b->job->priority()) return a->job->priority() > b->job->priority();
      return a->sequence < b->sequence;
    };
    queue_.insert(std::upper_bound(queue_.begin(), queue_.end(), entry, before), entry);
  }
  work_available_.notify_one();
  return true;
}

void Scheduler::job_changed() {
  std::lock_guard lock(mutex_);
  prune_locked();
}

void Scheduler::wait_idle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] {
    prune_locked();
    return queue_.empty();
  });
}

void Scheduler::stop(const std::string& reason) {
  std::vector<std::thread> workers;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (const auto& entry : queue_)
      if (entry->job->cancel(reason) == CancelResult::kCancelled)
        spdlog::info("job {} cancelled: {}", entry->job->id(), reason);
    workers.swap(workers_);
  }
  work_available_.notify_all();
  for (auto& worker : workers) worker.join();
  std::lock_guard lock(mutex_);
  queue_.clear();
  idle_.notify_all();
}

// Forgets finished jobs whose tasks have all returned, freeing their prepared scenes.
void Scheduler::prune_locked() {
  const auto removed = std::remove_if(queue_.begin(), queue_.end(), [](const auto& entry) {
    return entry->in_flight == 0 && entry->job->finished();
  });
  if (removed == queue_.end()) return;
  queue_.erase(removed, queue_.end());
  if (queue_.empty()) idle_.notify_all();
}

bool Scheduler::take_task_locked(Task& task) {
  prune_locked();
  for (const auto& entry : queue_) {
    if (entry->job->finished()) continue;  // tasks still in flight; nothing new to hand out
    if (!entry->prepared) {
      if (entry->preparing) continue;  // another worker is building it
      entry->preparing = true;
      task = Task{entry, true, {}};
    } else if (entry->next_tile < entry->tiles.size()) {
      task = Task{entry, false, entry->tiles[entry->next_tile++]};
    } else {
      continue;  // every tile handed out: lower-priority jobs may use this worker
    }
    ++entry->in_flight;
    return true;
  }
  return false;
}

void Scheduler::worker_loop() {
  for (;;) {
    Task task;
    {
      std::unique_lock lock(mutex_);
      work_available_.wait(lock, [&] { return stopping_ || take_task_locked(task); });
      if (!task.entry) return;  // stopping
    }
    if (task.prepare)
      prepare(*task.entry);
    else
      render(*task.entry, task.tile);
    {
      std::lock_guard lock(mutex_);
      --task.entry->in_flight;
      prune_locked();
    }
    // A prepared job has tiles for every idle worker; a finished one may free a waiter.
    work_available_.notify_all();
  }
}

void Scheduler::prepare(Entry& entry) {
  Job& job = *entry.job;
  std::shared_ptr<const PreparedScene> prepared;
  if (job.mark_running()) {
    try {
      prepared = options_.prepare(*entry.scene);
      if (!prepared) throw std::runtime_error("no scene was built");
    } catch (const std::exception& e) {
      job.fail(std::string("scene preparation failed: ") + e.what());
      spdlog::error("job {} failed: scene preparation failed: {}", job.id(), e.what());
    } catch (...) {
      job.fail("scene preparation failed: unknown error");
      spdlog::error("job {} failed: scene preparation failed: unknown error", job.id());
    }
  }
  if (prepared) {
    const auto& s = prepared->settings();
    spdlog::info("job {} started: {}x{}, {} spp, {} tiles, {}; prepared in {:.3f} s, BVH depth {}",
                 job.id(), s.width, s.height, s.samples_per_pixel, entry.tiles.size(),
                 prepared->features().summary(), prepared->build_seconds(), prepared->bvh_depth());
    if (options_.on_job_started) options_.on_job_started(job);
  }
  std::lock_guard lock(mutex_);
  entry.scene.reset();
  entry.prepared = std::move(prepared);
  entry.preparing = false;
}

void Scheduler::render(Entry& entry, const TileRect& rect) {
  Job& job = *entry.job;
  if (job.finished()) return;  // cancelled after the tile was handed out
  thread_local TilePasses passes;
  AddTileResult added = AddTileResult::kDropped;
  try {
    const TileStats stats = entry.prepared->render_tile(rect, passes);
    const std::uint32_t aovs = entry.prepared->settings().aovs;
    std::vector<std::uint8_t> exr =
        aovs == 0 ? encode_exr(passes.beauty, rect.width, rect.height, rect.x, rect.y)
                  : encode_exr(interleave_passes(passes, aovs), rect.width, rect.height,
                               output_channels(aovs), rect.x, rect.y);
    added = job.add_tile(rect, std::move(exr), stats.rays);
  } catch (const std::exception& e) {
    const std::string message = "tile " + std::to_string(rect.index) + " failed: " + e.what();
    if (job.fail(message)) spdlog::error("job {} failed: {}", job.id(), message);
  } catch (...) {
    const std::string message = "tile " + std::to_string(rect.index) + " failed: unknown error";
    if (job.fail(message)) spdlog::error("job {} failed: {}", job.id(), message);
  }
  if (options_.on_tile_rendered)
    options_.on_tile_rendered(job, rect, added != AddTileResult::kDropped);
  if (added == AddTileResult::kCompletedJob) {
    const JobInfo info = job.info();
    spdlog::info("job {} completed: {} tiles, {} rays in {:.3f} s, {:.3g} rays/s", info.id,
                 info.progress.tiles_done, info.progress.rays_traced, info.progress.elapsed_seconds,
                 info.progress.rays_per_second);
  }
}

}  // namespace tessera::server
