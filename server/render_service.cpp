#include "server/render_service.hpp"

#include <spdlog/spdlog.h>

#include "convert/scene_proto.hpp"
#include "server/job_proto.hpp"

namespace tessera::server {
namespace {

constexpr std::size_t kMaxNameLength = 256;

// No request, however malformed, may take the daemon down: whatever escapes a handler
// becomes INTERNAL for that call alone.
template <typename Fn>
grpc::Status guarded(const char* method, Fn&& fn) {
  try {
    return fn();
  } catch (const std::exception& e) {
    spdlog::error("{} failed: {}", method, e.what());
    return grpc::Status(grpc::StatusCode::INTERNAL, std::string(method) + ": " + e.what());
  } catch (...) {
    spdlog::error("{} failed with an unknown exception", method);
    return grpc::Status(grpc::StatusCode::INTERNAL, std::string(method) + ": unknown error");
  }
}

std::string cancelled_message(const std::string& job_id, const std::string& reason) {
  return "job " + job_id + " was cancelled" + (reason.empty() ? "" : " (" + reason + ")");
}

}  // namespace

RenderServiceImpl::RenderServiceImpl(JobStore& store, Scheduler& scheduler, SceneLimits limits,
                                     std::chrono::milliseconds poll_interval)
    : store_(store), scheduler_(scheduler), limits_(limits), poll_interval_(poll_interval) {}

std::shared_ptr<Job> RenderServiceImpl::find_job(const std::string& job_id,
                                                 grpc::Status& status) const {
  if (job_id.empty()) {
    status = grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "job_id: must not be empty");
    return nullptr;
  }
  auto job = store_.find(job_id);
  if (!job) status = grpc::Status(grpc::StatusCode::NOT_FOUND, "job '" + job_id + "' not found");
  return job;
}

grpc::Status RenderServiceImpl::SubmitJob(grpc::ServerContext*, const v1::SubmitJobRequest* request,
                                          v1::SubmitJobResponse* response) {
  return guarded("SubmitJob", [&] { return submit(*request, *response); });
}

grpc::Status RenderServiceImpl::submit(const v1::SubmitJobRequest& request,
                                       v1::SubmitJobResponse& response) {
  if (!accepting_)
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
  if (!request.has_scene())
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "scene: is required but missing");
  if (request.name().size() > kMaxNameLength)
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "name: must be at most " + std::to_string(kMaxNameLength) + " bytes, got " +
                            std::to_string(request.name().size()));
  SceneConversion conversion = scene_from_proto(request.scene(), request.settings(), limits_);
  if (!conversion.ok()) {
    const std::string message = describe_issues(conversion.issues);
    spdlog::info("rejected job '{}': {}", request.name(), message);
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message);
  }
  SceneDescription& scene = *conversion.scene;
  const RenderSettings settings = scene.render;
  const auto tiles = make_tiles(settings.width, settings.height, settings.tile_size).size();

  auto job = std::make_shared<Job>(ids_.next(), request.name(), request.priority(), settings,
                                   static_cast<std::uint32_t>(tiles), unix_millis_now());
  store_.add(job);
  // The response describes the job as submitted (QUEUED), before a worker can pick it up.
  job_info_to_proto(job->info(), *response.mutable_job());
  if (!scheduler_.submit(job, std::move(scene))) {
    job->cancel("daemon shutting down");
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
  }
  // The feature summary (with light count) is logged once the scene is prepared.
  spdlog::info("job {} '{}' submitted: priority {}, {}x{}, {} spp, depth {}, {} tiles", job->id(),
               job->name(), job->priority(), settings.width, settings.height,
               settings.samples_per_pixel, settings.max_depth, tiles);
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamTiles(grpc::ServerContext* context,
                                            const v1::StreamTilesRequest* request,
                                            grpc::ServerWriter<v1::Tile>* writer) {
  return guarded("StreamTiles", [&] { return stream(*context, request->job_id(), *writer); });
}

grpc::Status RenderServiceImpl::stream(grpc::ServerContext& context, const std::string& job_id,
                                       grpc::ServerWriter<v1::Tile>& writer) {
  grpc::Status status;
  const auto job = find_job(job_id, status);
  if (!job) return status;
  std::size_t sent = 0;
  v1::Tile message;
  for (;;) {
    if (context.IsCancelled())
      return grpc::Status(grpc::StatusCode::CANCELLED, "the client cancelled the stream");
    const TileUpdate update = job->wait_for_tiles(sent, poll_interval_);
    for (const FinishedTile& tile : update.tiles) {
      message.Clear();
      finished_tile_to_proto(job->id(), tile, message);
      if (!writer.Write(message))
        return grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
      ++sent;
    }
    // A finished job gains no tiles, so `update.tiles` held every one still unsent.
    if (!update.finished) continue;
    switch (update.state) {
      case JobState::kCompleted:
        return grpc::Status::OK;
      case JobState::kCancelled:
        return grpc::Status(grpc::StatusCode::CANCELLED,
                            cancelled_message(job->id(), update.cancel_reason));
      case JobState::kFailed:
        return grpc::Status(grpc::StatusCode::ABORTED,
                            "job " + job->id() + " failed: " + update.error);
      default:
        break;
    }
    return grpc::Status(grpc::StatusCode::INTERNAL, "job ended in an unexpected state");
  }
}

grpc::Status RenderServiceImpl::GetJob(grpc::ServerContext*, const v1::GetJobRequest* request,
                                       v1::Job* response) {
  return guarded("GetJob", [&] {
    grpc::Status status;
    const auto job = find_job(request->job_id(), status);
    if (job) job_info_to_proto(job->info(), *response);
    return status;
  });
}

grpc::Status RenderServiceImpl::ListJobs(grpc::ServerContext*, const v1::ListJobsRequest*,
                                         v1::ListJobsResponse* response) {
  return guarded("ListJobs", [&] {
    for (const auto& job : store_.list()) job_info_to_proto(job->info(), *response->add_jobs());
    return grpc::Status::OK;
  });
}

grpc::Status RenderServiceImpl::CancelJob(grpc::ServerContext*, const v1::CancelJobRequest* request,
                                          v1::CancelJobResponse* response) {
  return guarded("CancelJob", [&] { return cancel(request->job_id(), *response); });
}

grpc::Status RenderServiceImpl::cancel(const std::string& job_id, v1::CancelJobResponse& response) {
  grpc::Status status;
  const auto job = find_job(job_id, status);
  if (!job) return status;
  const CancelResult result = job->cancel("requested by a client");
  const JobInfo info = job->info();
  if (result == CancelResult::kAlreadyFinished)
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "job " + job_id + " has already " + to_string(info.state));
  if (result == CancelResult::kCancelled) {
    scheduler_.job_changed();
    spdlog::info("job {} cancelled by a client after {}/{} tiles", job_id, info.progress.tiles_done,
                 info.progress.tiles_total);
  }
  job_info_to_proto(info, *response.mutable_job());
  return grpc::Status::OK;
}

}  // namespace tessera::server
