#include "server/scheduler.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <optional>
#include <stdexcept>

#include "server/job_passes.hpp"
#include "server/metrics.hpp"
#include "server/structured_log.hpp"
#include "server/tile_state_codec.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/output_channels.hpp"
#include "tessera/render/tile_accumulation.hpp"
#include "tessera/render/tile_cancel.hpp"

namespace tessera::server {

// A job as the scheduler sees it. Guarded by Scheduler::mutex_, except `scene`, which only
// the one worker that set `preparing` touches.
struct Scheduler::Entry {
  std::shared_ptr<Job> job;
  std::uint64_t sequence = 0;
  std::unique_ptr<SceneDescription> scene;  // released once prepared; null: load_scene
  std::shared_ptr<const PreparedScene> prepared;
  std::vector<TileWork> tiles;  // those still to render, known once prepared
  std::size_t next_tile = 0;    // tiles before it have been handed out
  // Per grid tile: a pass of it is being rendered. The next pass of that tile waits (it
  // continues the state that pass stores), so the job's work waits behind it.
  std::vector<bool> rendering;
  bool preparing = false;
  unsigned in_flight = 0;  // tasks of this entry running on workers
  // Replaced by a new entry (requeue): hands out nothing more.
  bool retired = false;
  // Per device (SchedulerOptions::devices, same order): it takes this job's tiles. Set
  // when the job is prepared.
  std::vector<bool> device_accepts;
  // Queued as a fresh entry once this one's tasks have returned (requeue): the job's live
  // object, which may differ from `job` (a worker may still be using `job`).
  std::shared_ptr<Job> successor;
  // Tiles (passes) this entry's workers rendered: [0] the CPU threads, [1 + d] device d;
  // and those that failed on a device and went to the CPU. Counted before the tile is
  // stored, so the worker that stores the last one reads them all.
  std::array<std::atomic<std::uint32_t>, kMaxTileWorkers> rendered_by{};
  std::atomic<std::uint32_t> fell_back{0};
};

// The queue's order: priority descending (it may change: UpdateJob), then submission.
bool Scheduler::queue_order(const std::shared_ptr<Entry>& a, const std::shared_ptr<Entry>& b) {
  const int pa = a->job->priority();
  const int pb = b->job->priority();
  if (pa != pb) return pa > pb;
  return a->sequence < b->sequence;
}

struct Scheduler::Task {
  std::shared_ptr<Entry> entry;
  bool prepare = false;
  std::vector<TileWork> tiles;  // one, or for a device with batch_pixels, consecutive ones
};

Scheduler::Scheduler(SchedulerOptions options) : options_(std::move(options)) {
  if (options_.threads == 0) throw std::invalid_argument("scheduler needs at least one thread");
  if (!options_.prepare) options_.prepare = default_prepare;
  if (options_.devices.size() + 1 > kMaxTileWorkers)
    throw std::invalid_argument("scheduler: more than " + std::to_string(kMaxTileWorkers - 1) +
                                " devices");
  if (options_.metrics) {
    std::vector<std::string> names{"cpu"};
    for (const auto& device : options_.devices) names.push_back(device->name());
    options_.metrics->name_tile_workers(std::move(names));
  }
}

Scheduler::~Scheduler() {
  stop();
}

void Scheduler::start() {
  std::lock_guard lock(mutex_);
  if (stopping_ || !workers_.empty()) return;
  workers_.reserve(options_.threads + options_.devices.size());
  for (unsigned i = 0; i < options_.threads; ++i)
    workers_.emplace_back([this] { worker_loop(kCpuWorker); });
  for (std::size_t d = 0; d < options_.devices.size(); ++d)
    workers_.emplace_back([this, d] { worker_loop(d); });
}

namespace {

// Store tiles of a job: its tiles times its passes.
std::size_t tile_count(const RenderSettings& r) {
  return PassLayout(r).units();
}

// Failing a job writes to the store, which can itself fail (a full disk); that must not
// take the worker thread down with it.
void fail_job(Job& job, const std::string& message) {
  try {
    if (job.fail(message))
      log_event(spdlog::level::err, "job_failed", {{"job_id", job.id()}, {"error", message}},
                fmt::format("job {} failed: {}", job.id(), message));
  } catch (const std::exception& e) {
    spdlog::error("job {} failed ({}) and the failure could not be stored: {}", job.id(), message,
                  e.what());
    job.request_stop();
  }
}

}  // namespace

bool Scheduler::submit(std::shared_ptr<Job> job, SceneDescription scene) {
  if (tile_count(scene.render) != job->record().tiles_total)
    throw std::logic_error("job " + job->id() + " has a tile count that does not match its scene");
  auto entry = std::make_shared<Entry>();
  entry->job = std::move(job);
  entry->scene = std::make_unique<SceneDescription>(std::move(scene));
  return enqueue(std::move(entry));
}

bool Scheduler::submit(std::shared_ptr<Job> job) {
  if (!options_.load_scene) throw std::logic_error("scheduler has no load_scene to read scenes");
  auto entry = std::make_shared<Entry>();
  entry->job = std::move(job);
  return enqueue(std::move(entry));
}

bool Scheduler::enqueue(std::shared_ptr<Entry> entry) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    entry->sequence = next_sequence_++;
    queue_.insert(std::upper_bound(queue_.begin(), queue_.end(), entry, queue_order), entry);
  }
  work_available_.notify_one();
  return true;
}

void Scheduler::job_changed() {
  {
    std::lock_guard lock(mutex_);
    // Priorities may have changed (UpdateJob): keep the queue in its order.
    std::stable_sort(queue_.begin(), queue_.end(), queue_order);
    prune_locked();
  }
  work_available_.notify_all();
}

bool Scheduler::requeue(std::shared_ptr<Job> job) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    bool waiting = false;
    for (const auto& entry : queue_) {
      if (entry->job->id() != job->id() || entry->retired) continue;
      entry->retired = true;
      if (entry->in_flight > 0 && !waiting) {
        entry->successor = job;
        waiting = true;
      }
    }
    if (waiting) return true;
  }
  auto entry = std::make_shared<Entry>();
  entry->job = std::move(job);
  return enqueue(std::move(entry));
}

void Scheduler::wait_idle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] {
    prune_locked();
    return queue_.empty() || (stopping_ && in_flight_ == 0);
  });
}

void Scheduler::stop(std::chrono::milliseconds grace) {
  std::vector<std::thread> workers;
  {
    std::unique_lock lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    work_available_.notify_all();
    if (!idle_.wait_for(lock, grace, [&] { return in_flight_ == 0; })) {
      unsigned aborted = 0;
      for (const auto& entry : queue_)
        if (entry->in_flight > 0) {
          entry->job->request_stop();
          aborted += entry->in_flight;
        }
      spdlog::info(
          "{} tiles still rendering after the {} ms grace period are abandoned; they "
          "are rendered again after a restart",
          aborted, grace.count());
    }
    workers.swap(workers_);
  }
  work_available_.notify_all();
  for (auto& worker : workers) worker.join();
  std::lock_guard lock(mutex_);
  queue_.clear();
  idle_.notify_all();
}

// Forgets finished, paused and retired entries whose tasks have all returned, freeing
// their prepared scenes (a resumed job is prepared again).
void Scheduler::prune_locked() {
  std::vector<std::shared_ptr<Entry>> requeued;
  const auto removed = std::remove_if(queue_.begin(), queue_.end(), [&](const auto& entry) {
    if (entry->in_flight != 0) return false;
    if (entry->retired) {
      if (entry->successor && !entry->successor->finished()) {
        auto fresh = std::make_shared<Entry>();
        fresh->job = std::move(entry->successor);
        requeued.push_back(std::move(fresh));
      }
      return true;
    }
    const JobState state = entry->job->state();
    if (state == JobState::kPaused) return true;
    if (!is_finished(state)) return false;
    if (options_.on_job_released) options_.on_job_released(*entry->job);
    return true;
  });
  if (removed == queue_.end()) return;
  queue_.erase(removed, queue_.end());
  for (auto& entry : requeued) {
    entry->sequence = next_sequence_++;
    queue_.push_back(std::move(entry));
  }
  if (!requeued.empty()) std::stable_sort(queue_.begin(), queue_.end(), queue_order);
  // Submitters with nothing queued start afresh.
  std::erase_if(last_served_, [&](const auto& served) {
    return std::none_of(queue_.begin(), queue_.end(),
                        [&](const auto& entry) { return entry->job->submitter() == served.first; });
  });
  if (queue_.empty()) idle_.notify_all();
}

namespace {

template <typename Entry>
bool has_work(const Entry& entry) {
  if (entry.retired) return false;
  // Finished (tasks still in flight) or paused: nothing new to hand out.
  if (!is_runnable(entry.job->state())) return false;
  if (!entry.prepared) return !entry.preparing;
  if (entry.next_tile >= entry.tiles.size()) return false;  // every tile is handed out
  // The next pass of a tile whose previous pass is still rendering waits for it.
  return !entry.rendering[entry.tiles[entry.next_tile].rect.index];
}

}  // namespace

bool Scheduler::take_task_locked(Task& task, std::size_t device) {
  prune_locked();
  if (stopping_) return false;
  // A device worker sees only the prepared jobs that device accepts; the rest of the queue
  // (and preparing jobs) is the CPU workers'.
  const auto available = [&](const Entry& entry) {
    if (!has_work(entry)) return false;
    if (device == kCpuWorker)  // preparation is the CPU's; a GPU job's tiles are not
      return !entry.prepared || entry.prepared->settings().device != RenderDevice::kGpu;
    return entry.prepared && device < entry.device_accepts.size() && entry.device_accepts[device];
  };
  // queue_ is ordered by priority, then submission: the first entry with work sets the
  // priority, and the least recently served submitter at that priority gets the task.
  std::shared_ptr<Entry> chosen;
  std::uint64_t chosen_served = 0;
  for (const auto& entry : queue_) {
    if (!available(*entry)) continue;
    if (chosen && entry->job->priority() != chosen->job->priority()) break;
    const auto it = last_served_.find(entry->job->submitter());
    const std::uint64_t served = it == last_served_.end() ? 0 : it->second;
    if (!chosen || served < chosen_served) {
      chosen = entry;
      chosen_served = served;
      if (served == 0) break;  // never served: none can come before it
    }
  }
  if (!chosen) return false;
  if (chosen->prepared && options_.yield_every > 0 &&
      chosen->next_tile >= options_.long_job_tiles && (served_ + 1) % options_.yield_every == 0) {
    for (const auto& entry : queue_)
      if (entry->job->priority() < chosen->job->priority() && available(*entry)) {
        chosen = entry;
        break;
      }
  }
  if (!chosen->prepared) {
    chosen->preparing = true;
    task = Task{chosen, true, {}};
  } else {
    task = Task{chosen, false, {chosen->tiles[chosen->next_tile++]}};
    chosen->rendering[task.tiles[0].rect.index] = true;
    ++served_;
    // A device that renders many pixels at once takes the job's next tiles with it.
    const std::size_t batch = device == kCpuWorker ? 0 : options_.devices[device]->batch_pixels();
    std::size_t pixels = task.tiles[0].rect.pixel_count();
    while (chosen->next_tile < chosen->tiles.size()) {
      const TileWork& next = chosen->tiles[chosen->next_tile];
      if (chosen->rendering[next.rect.index] || pixels + next.rect.pixel_count() > batch) break;
      task.tiles.push_back(next);
      chosen->rendering[next.rect.index] = true;
      pixels += next.rect.pixel_count();
      ++chosen->next_tile;
    }
  }
  last_served_[chosen->job->submitter()] = served_ + 1;
  ++chosen->in_flight;
  ++in_flight_;
  return true;
}

void Scheduler::worker_loop(std::size_t device) {
  for (;;) {
    Task task;
    {
      std::unique_lock lock(mutex_);
      work_available_.wait(lock, [&] { return stopping_ || take_task_locked(task, device); });
      if (!task.entry) return;  // stopping
    }
    if (task.prepare)
      prepare(*task.entry);
    else
      render(*task.entry, task.tiles, device);
    {
      std::lock_guard lock(mutex_);
      for (const TileWork& work : task.tiles) task.entry->rendering[work.rect.index] = false;
      --task.entry->in_flight;
      --in_flight_;
      prune_locked();
      if (in_flight_ == 0) idle_.notify_all();
    }
    // A prepared job has tiles for every idle worker; a finished one may free a waiter.
    work_available_.notify_all();
  }
}

std::vector<bool> Scheduler::devices_for(const Job& job, const PreparedScene& scene) const {
  // Asked on the CPU worker that prepares the job: a GPU's answer builds the scene's device
  // layout (PreparedScene::device_source), which must not hold the lock.
  const RenderSettings& r = scene.settings();
  std::vector<bool> accepts(options_.devices.size(), false);
  if (r.device == RenderDevice::kCpu) return accepts;
  std::string why_not;
  if (options_.devices.empty()) {
    why_not = "this daemon renders on no GPU";
  } else if (r.pass_count() > 1) {
    why_not = "GPUs render one-pass jobs";
  } else {
    for (std::size_t d = 0; d < options_.devices.size(); ++d) {
      try {
        accepts[d] = options_.devices[d]->accepts(scene);
      } catch (const std::exception& e) {
        spdlog::warn("job {}: {} cannot take its tiles: {}", job.id(), options_.devices[d]->name(),
                     e.what());
      }
    }
    // The reason is only for a job that must have a GPU: device_source is a BVH build.
    if (r.device == RenderDevice::kGpu &&
        std::find(accepts.begin(), accepts.end(), true) == accepts.end()) {
      const std::string& unsupported = scene.device_source().unsupported;
      why_not = "no GPU of this daemon takes the scene" +
                (unsupported.empty() ? std::string() : " (" + unsupported + ")");
    }
  }
  if (r.device == RenderDevice::kGpu && !why_not.empty())
    throw std::runtime_error("render.device is gpu, but " + why_not);
  return accepts;
}

void Scheduler::prepare(Entry& entry) {
  Job& job = *entry.job;
  std::shared_ptr<const PreparedScene> prepared;
  std::vector<bool> device_accepts(options_.devices.size(), false);
  std::vector<TileWork> pending;
  std::size_t stored = 0;
  std::size_t grid_tiles = 0;
  try {
    // A job's first start is the one that ends its wait in the queue (a resumed or
    // restarted job has a start time already).
    const bool first_start = job.record().started_unix_ms == 0;
    if (job.mark_running()) {
      if (options_.metrics && first_start) {
        const JobRecord started = job.record();
        options_.metrics->job_started(
            static_cast<double>(started.started_unix_ms - started.submitted_unix_ms) / 1000.0);
      }
      // Preparation, as rays per second and /metrics count it, includes reading the scene
      // back from the store and converting it.
      const auto load_start = std::chrono::steady_clock::now();
      std::optional<SceneDescription> loaded;
      if (!entry.scene) loaded = options_.load_scene(job);
      const SceneDescription& scene = entry.scene ? *entry.scene : *loaded;
      const RenderSettings& r = scene.render;
      if (tile_count(r) != job.record().tiles_total)
        throw std::runtime_error("the stored scene's tile grid does not match the job's");
      const auto prepare_start = std::chrono::steady_clock::now();
      prepared = options_.prepare(scene);
      if (!prepared) throw std::runtime_error("no scene was built");
      const std::chrono::duration<double> took = std::chrono::steady_clock::now() - prepare_start;
      const std::chrono::duration<double> preparation =
          std::chrono::steady_clock::now() - load_start;
      if (options_.metrics) options_.metrics->scene_prepared(preparation.count());
      job.add_prepare_time(std::chrono::duration_cast<std::chrono::milliseconds>(preparation));
      if (options_.prepare_timeout.count() > 0 && took > options_.prepare_timeout)
        throw std::runtime_error(
            fmt::format("it took {:.1f} s, longer than the daemon's limit of {:.1f} s "
                        "(prepare_timeout in its configuration)",
                        took.count(), options_.prepare_timeout.count() / 1000.0));
      device_accepts = devices_for(job, *prepared);
      // Tiles (and passes of tiles) stored before, by a daemon that stopped or died, are
      // not rendered again. Work is in store-index order: pass 1 of every tile, then pass 2.
      const std::vector<std::uint32_t> done = job.stored_tile_indices();
      stored = done.size();
      const std::vector<TileRect> grid = make_tiles(r.width, r.height, r.tile_size);
      grid_tiles = grid.size();
      const PassLayout layout(r);
      for (std::uint32_t unit = 0; unit < layout.units(); ++unit)
        if (!std::binary_search(done.begin(), done.end(), unit)) {
          const TilePass tile_pass = layout.of(unit);
          pending.push_back(TileWork{grid[tile_pass.tile], tile_pass.pass, unit});
        }
    }
  } catch (const std::exception& e) {
    prepared.reset();
    fail_job(job, std::string("scene preparation failed: ") + e.what());
  } catch (...) {
    prepared.reset();
    fail_job(job, "scene preparation failed: unknown error");
  }
  if (prepared) {
    const auto& s = prepared->settings();
    log_event(spdlog::level::info, "job_started",
              {{"job_id", job.id()},
               {"tiles", static_cast<std::uint64_t>(pending.size() + stored)},
               {"tiles_stored_before", static_cast<std::uint64_t>(stored)},
               {"features", prepared->features().summary()},
               {"prepare_seconds", prepared->build_seconds()},
               {"bvh_depth", static_cast<std::int64_t>(prepared->bvh_depth())}},
              fmt::format("job {} started: {}x{}, {} spp in {} passes, {} tile passes ({} stored "
                          "before), {}; prepared in {:.3f} s, BVH depth {}",
                          job.id(), s.width, s.height, s.samples_per_pixel, s.pass_count(),
                          pending.size() + stored, stored, prepared->features().summary(),
                          prepared->build_seconds(), prepared->bvh_depth()));
    if (options_.on_job_started) options_.on_job_started(job);
  }
  std::lock_guard lock(mutex_);
  entry.device_accepts = std::move(device_accepts);
  entry.scene.reset();
  entry.tiles = std::move(pending);
  entry.rendering.assign(grid_tiles, false);
  entry.prepared = std::move(prepared);
  entry.preparing = false;
}

namespace {

std::vector<std::uint8_t> tile_exr(const TilePasses& passes, const TileRect& rect,
                                   std::uint32_t aovs) {
  return aovs == 0 ? encode_exr(passes.beauty, rect.width, rect.height, rect.x, rect.y)
                   : encode_exr(interleave_passes(passes, aovs), rect.width, rect.height,
                                output_channels(aovs), rect.x, rect.y);
}

}  // namespace

void Scheduler::count_trace(const TileStats& stats,
                            std::chrono::steady_clock::time_point start) const {
  if (!options_.metrics) return;
  const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
  options_.metrics->tile_traced(stats.rays, took.count());
}

std::uint64_t Scheduler::tile_samples(const PreparedScene& scene, const TileWork& work) {
  const PassLayout layout(scene.settings());
  const std::uint64_t pixels = std::uint64_t{work.rect.width} * work.rect.height;
  const std::uint32_t before = work.pass > 1 ? layout.samples_after(work.pass - 1) : 0;
  return pixels * (layout.samples_after(work.pass) - before);
}

SchedulerLoad Scheduler::load() {
  std::lock_guard lock(mutex_);
  SchedulerLoad load;
  load.in_flight = in_flight_;
  for (const auto& entry : queue_) {
    if (entry->retired || !is_runnable(entry->job->state())) continue;
    if (!entry->prepared) {
      ++load.jobs_with_work;
      continue;
    }
    const std::size_t left = entry->tiles.size() - std::min(entry->next_tile, entry->tiles.size());
    if (left > 0) ++load.jobs_with_work;
    load.pending_tiles += left;
  }
  return load;
}

std::optional<AddTileResult> Scheduler::render_pass(Entry& entry, const TileWork& work) {
  Job& job = *entry.job;
  const PreparedScene& scene = *entry.prepared;
  const PassLayout layout(scene.settings());
  const TileRect& rect = work.rect;
  // Continues the state the previous pass stored; kept per worker only while it renders,
  // so memory does not grow with the job's tiles.
  thread_local TileAccumulation state;
  state = TileAccumulation{};
  if (work.pass > 1) {
    const std::optional<TilePassState> stored = job.tile_pass_state(rect.index);
    if (!stored || stored->passes_done != work.pass - 1)
      throw std::logic_error("pass " + std::to_string(work.pass) + " has no stored state of pass " +
                             std::to_string(work.pass - 1) + " to continue");
    state = decode_tile_state(stored->bytes);
  }
  TileStats stats;
  {
    const TileCancelScope cancel(&job.stop_flag());
    const auto trace_start = std::chrono::steady_clock::now();
    stats = scene.accumulate_tile(rect, state, layout.samples_after(work.pass));
    count_trace(stats, trace_start);
  }
  count_rendered(entry, 0);  // passes are the CPU's
  // A raised flag may have cut the pass short: it is incomplete, so never stored.
  if (job.stop_requested()) return std::nullopt;
  const bool last = work.pass == layout.passes();
  TilePassState kept;
  kept.tile = rect.index;
  kept.passes_done = work.pass;
  if (!last) kept.bytes = encode_tile_state(state);
  const std::vector<std::uint8_t> exr =
      tile_exr(accumulated_image(state), rect, scene.settings().aovs);
  return job.add_tile_pass(work.unit, options_.owner, exr, stats.rays, kept, last);
}

void Scheduler::count_rendered(Entry& entry, std::size_t worker, std::size_t tiles) const {
  entry.rendered_by[worker].fetch_add(static_cast<std::uint32_t>(tiles), std::memory_order_relaxed);
  if (options_.metrics) options_.metrics->tile_rendered_by(worker, tiles);
}

void Scheduler::render_whole_tiles(Entry& entry, std::span<const TileRect> rects,
                                   std::size_t device, std::span<TilePasses> passes,
                                   std::span<TileStats> stats) {
  if (device != kCpuWorker) {
    TileDevice& on = *options_.devices[device];
    try {
      const std::vector<TileStats> got = on.render_tiles(entry.prepared, rects, passes);
      if (got.size() != rects.size())
        throw std::logic_error(std::to_string(got.size()) + " results for " +
                               std::to_string(rects.size()) + " tiles");
      std::copy(got.begin(), got.end(), stats.begin());
      count_rendered(entry, 1 + device, rects.size());
      return;
    } catch (const std::exception& e) {
      if (rects.size() == 1)
        spdlog::warn("job {}: tile {} failed on {}, rendering it on the CPU: {}", entry.job->id(),
                     rects[0].index, on.name(), e.what());
      else
        spdlog::warn(
            "job {}: a batch of {} tiles from tile {} failed on {}, rendering them on "
            "the CPU: {}",
            entry.job->id(), rects.size(), rects[0].index, on.name(), e.what());
      entry.fell_back.fetch_add(static_cast<std::uint32_t>(rects.size()),
                                std::memory_order_relaxed);
      if (options_.metrics) options_.metrics->tile_fell_back(device, rects.size());
    }
  }
  for (std::size_t i = 0; i < rects.size(); ++i)
    stats[i] = entry.prepared->render_tile(rects[i], passes[i]);
  count_rendered(entry, 0, rects.size());
}

std::string Scheduler::tile_split(const Entry& entry) const {
  std::string split = fmt::format("cpu {}", entry.rendered_by[0].load(std::memory_order_relaxed));
  for (std::size_t d = 0; d < options_.devices.size(); ++d)
    split += fmt::format(", {} {}", options_.devices[d]->name(),
                         entry.rendered_by[1 + d].load(std::memory_order_relaxed));
  if (const std::uint32_t back = entry.fell_back.load(std::memory_order_relaxed); back != 0)
    split += fmt::format(" ({} failed on a device and went to the CPU)", back);
  return split;
}

// One tile of a task: its claim and what became of it.
struct Scheduler::Attempt {
  const TileWork* work = nullptr;
  bool claimed = false;
  AddTileResult added = AddTileResult::kDropped;
  std::optional<std::string> failure;
};

void Scheduler::render(Entry& entry, std::span<const TileWork> works, std::size_t device) {
  Job& job = *entry.job;
  // Cancelled or paused after the tiles were handed out (a resumed job is queued afresh).
  if (job.stop_requested() || !is_runnable(job.state())) return;
  const std::uint64_t run = job.run();
  std::vector<Attempt> attempts;
  attempts.reserve(works.size());
  for (const TileWork& work : works) {
    Attempt attempt;
    attempt.work = &work;
    try {
      if (!job.claim_tile(work.unit, options_.owner)) continue;  // stored, or another's
      attempt.claimed = true;
      if (options_.on_tile_started) options_.on_tile_started(job, work.rect);
    } catch (const std::exception& e) {
      attempt.failure = e.what();
    } catch (...) {
      attempt.failure = "unknown error";
    }
    attempts.push_back(std::move(attempt));
  }
  if (entry.prepared->settings().pass_count() > 1) {
    for (Attempt& attempt : attempts) {  // the CPU's, one tile per task
      if (!attempt.claimed || attempt.failure) continue;
      try {
        if (const std::optional<AddTileResult> committed = render_pass(entry, *attempt.work)) {
          attempt.added = *committed;
          attempt.claimed = false;  // committed or released by add_tile_pass
        }
      } catch (const std::exception& e) {
        attempt.failure = e.what();
      } catch (...) {
        attempt.failure = "unknown error";
      }
    }
  } else {
    render_and_store(entry, attempts, device, run);
  }
  for (const Attempt& attempt : attempts) finish(entry, attempt, run);
}

void Scheduler::render_and_store(Entry& entry, std::vector<Attempt>& attempts, std::size_t device,
                                 std::uint64_t run) {
  Job& job = *entry.job;
  std::vector<Attempt*> rendering;
  std::vector<TileRect> rects;
  for (Attempt& attempt : attempts)
    if (attempt.claimed && !attempt.failure) {
      rendering.push_back(&attempt);
      rects.push_back(attempt.work->rect);
    }
  if (rendering.empty()) return;
  thread_local std::vector<TilePasses> passes;
  if (passes.size() < rendering.size()) passes.resize(rendering.size());
  std::vector<TileStats> stats(rendering.size());
  try {
    const TileCancelScope cancel(&job.stop_flag());
    const auto trace_start = std::chrono::steady_clock::now();
    render_whole_tiles(entry, rects, device, std::span(passes).first(rendering.size()), stats);
    TileStats total;
    for (const TileStats& s : stats) total.rays += s.rays;
    count_trace(total, trace_start);
  } catch (const std::exception& e) {
    for (Attempt* attempt : rendering) attempt->failure = e.what();
    return;
  } catch (...) {
    for (Attempt* attempt : rendering) attempt->failure = "unknown error";
    return;
  }
  for (std::size_t i = 0; i < rendering.size(); ++i) {
    Attempt& attempt = *rendering[i];
    // A raised flag may have cut the tile short: it is incomplete, so never stored. The
    // flag first, then the run (see Job::run).
    if (job.stop_flag().load() || job.run() != run) return;
    try {
      attempt.added = job.add_tile(rects[i], options_.owner,
                                   tile_exr(passes[i], rects[i], entry.prepared->settings().aovs),
                                   stats[i].rays);
      attempt.claimed = false;  // committed or released by add_tile
    } catch (const std::exception& e) {
      attempt.failure = e.what();
    } catch (...) {
      attempt.failure = "unknown error";
    }
  }
}

void Scheduler::finish(Entry& entry, const Attempt& attempt, std::uint64_t run) {
  Job& job = *entry.job;
  const TileWork& work = *attempt.work;
  if (attempt.claimed) {
    try {
      job.release_tile(work.unit, options_.owner);
    } catch (...) {
      // Claims lapse anyway; nothing is lost by keeping this one.
    }
  }
  // An attempt that failed because its job stopped meanwhile is not the tile's fault.
  if (attempt.failure && !job.stop_flag().load() && job.run() == run)
    tile_failed(entry, work, *attempt.failure);
  const bool kept = attempt.added != AddTileResult::kDropped;
  if (options_.metrics && kept) options_.metrics->tile_stored(tile_samples(*entry.prepared, work));
  if (options_.on_tile_rendered) options_.on_tile_rendered(job, work.rect, kept);
  if (attempt.added == AddTileResult::kCompletedJob) {
    const JobInfo info = job.info();
    const std::string split = tile_split(entry);
    log_event(spdlog::level::info, "job_completed",
              {{"job_id", info.id},
               {"tiles", static_cast<std::uint64_t>(info.progress.tiles_done)},
               {"rays", info.progress.rays_traced},
               {"elapsed_seconds", info.progress.elapsed_seconds},
               {"rays_per_second", info.progress.rays_per_second},
               {"tiles_rendered_by", split}},
              fmt::format("job {} completed: {} tiles, {} rays in {:.3f} s, {:.3g} rays/s; tiles "
                          "rendered by {}",
                          info.id, info.progress.tiles_done, info.progress.rays_traced,
                          info.progress.elapsed_seconds, info.progress.rays_per_second, split));
  }
}

void Scheduler::tile_failed(Entry& entry, const TileWork& work, const std::string& reason) {
  Job& job = *entry.job;
  const TileRect& rect = work.rect;
  const std::string pass = entry.prepared && entry.prepared->settings().pass_count() > 1
                               ? " pass " + std::to_string(work.pass)
                               : "";
  const std::string tile = "tile " + std::to_string(rect.index) + pass + " (x " +
                           std::to_string(rect.x) + ", y " + std::to_string(rect.y) + ")";
  std::uint32_t failures = 0;
  try {
    // Counted per unit of work: a tile's passes fail and retry independently.
    failures = job.record_tile_failure(work.unit);
  } catch (const std::exception& e) {
    fail_job(job, tile + " failed: " + reason + "; its failure could not be counted: " + e.what());
    return;
  }
  if (failures > options_.tile_retries) {
    fail_job(job, tile + " failed " + std::to_string(failures) +
                      (failures == 1 ? " time: " : " times: ") + reason);
    return;
  }
  spdlog::warn("job {}: {} failed (attempt {} of {}), retrying: {}", job.id(), tile, failures,
               options_.tile_retries + 1, reason);
  {
    std::lock_guard lock(mutex_);
    entry.tiles.push_back(work);  // handed out again after the tiles still waiting
  }
  work_available_.notify_one();
}

}  // namespace tessera::server
