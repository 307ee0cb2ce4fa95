#include "server/render_service.hpp"

#include <spdlog/spdlog.h>

#include <charconv>

#include "convert/scene_proto.hpp"
#include "server/job_cost.hpp"
#include "server/job_labels.hpp"
#include "server/job_passes.hpp"
#include "server/job_proto.hpp"
#include "server/log_text.hpp"
#include "server/request_id.hpp"
#include "server/rpc_handler.hpp"
#include "server/structured_log.hpp"

namespace tessera::server {
using rpc::guarded;
using rpc::invalid;
using rpc::permission_denied;
using rpc::unary;
namespace {

// Tiles read from the store per batch while streaming: bounds a stream's memory whatever
// the job's size.
constexpr std::size_t kTilesPerRead = 16;

std::string cancelled_message(const std::string& job_id, const std::string& reason) {
  return "job " + job_id + " was cancelled" + (reason.empty() ? "" : " (" + reason + ")");
}

// The host part of a gRPC peer ("ipv4:10.0.0.7:51234" -> "ipv4:10.0.0.7"): a client that
// names no submitter is known by its machine, not by its connection.
std::string peer_host(const std::string& peer) {
  if (peer.rfind("ipv4:", 0) == 0 || peer.rfind("ipv6:", 0) == 0) {
    const auto colon = peer.rfind(':');
    if (colon > 5) return peer.substr(0, colon);
  }
  return peer;
}

}  // namespace

RenderServiceImpl::RenderServiceImpl(JobRegistry& jobs, Scheduler& scheduler, SceneLimits limits,
                                     std::size_t max_jobs_per_submitter,
                                     std::chrono::milliseconds poll_interval,
                                     std::chrono::milliseconds stream_write_timeout)
    : jobs_(jobs),
      scheduler_(scheduler),
      limits_(limits),
      max_jobs_per_submitter_(max_jobs_per_submitter),
      poll_interval_(poll_interval),
      write_watchdog_(stream_write_timeout) {}

std::shared_ptr<Job> RenderServiceImpl::find_job(const std::string& job_id, const Caller& caller,
                                                 grpc::Status& status) const {
  if (job_id.empty()) {
    status = invalid("job_id: must not be empty");
    return nullptr;
  }
  // Not echoed: an id this long is not one of ours, and a reply or log line must not
  // become a carrier for whatever it holds.
  if (job_id.size() > kMaxJobIdLength) {
    status = invalid("job_id: must be at most " + std::to_string(kMaxJobIdLength) + " bytes, got " +
                     std::to_string(job_id.size()));
    return nullptr;
  }
  auto job = const_cast<JobRegistry&>(jobs_).find(job_id);
  if (!job) {
    status = grpc::Status(grpc::StatusCode::NOT_FOUND,
                          "job '" + escape_client_text(job_id) + "' not found");
    return nullptr;
  }
  if (!caller.may_act_on(job->submitter())) {
    status = permission_denied("job " + job->id() + " belongs to another submitter; token '" +
                               caller.name + "' (role submit) reaches only its own jobs");
    return nullptr;
  }
  return job;
}

grpc::Status RenderServiceImpl::StreamedSubmitJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::SubmitJobRequest, v1::SubmitJobResponse>* streamer) {
  return unary("SubmitJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return submit(*context, caller, request, response);
               });
}

grpc::Status RenderServiceImpl::submit(grpc::ServerContext& context, const Caller& caller,
                                       const v1::SubmitJobRequest& request,
                                       v1::SubmitJobResponse& response) {
  if (!accepting_)
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
  if (!request.has_scene()) return invalid("scene: is required but missing");
  if (request.name().size() > kMaxJobNameLength)
    return invalid("name: must be at most " + std::to_string(kMaxJobNameLength) + " bytes, got " +
                   std::to_string(request.name().size()));
  if (request.submitter().size() > kMaxSubmitterLength)
    return invalid("submitter: must be at most " + std::to_string(kMaxSubmitterLength) +
                   " bytes, got " + std::to_string(request.submitter().size()));
  if (!request.submitter().empty() && !caller.may_act_on(request.submitter()))
    return permission_denied("submitter: token '" + caller.name + "' submits as '" + caller.name +
                             "' only; leave submitter empty");
  const JobLabels labels(request.labels().begin(), request.labels().end());
  if (const auto problem = labels_problem(labels, "labels")) return invalid(*problem);
  if (const auto problem = request_id_problem(request.request_id())) return invalid(*problem);
  const std::string logged_name = escape_client_text(request.name());
  // Without tokens a job is its requester's, or else its machine's; with tokens the
  // token's, unless an admin submits on someone's behalf. Request ids are per submitter.
  const std::string submitter = !request.submitter().empty() ? request.submitter()
                                : caller.authenticated()     ? caller.name
                                                             : peer_host(context.peer());
  // A retry finds its job before paying for the scene again, so it answers quickly even
  // when the first attempt's scene took longer than the client's deadline.
  std::string fingerprint;
  if (!request.request_id().empty()) {
    fingerprint = request_fingerprint(request);
    if (auto existing = jobs_.store().find_job_by_request(submitter, request.request_id()))
      return answer_retry(caller, *existing, fingerprint, response);
  }
  // Before the scene is converted: a request that could never fit costs no more than the
  // memory gRPC already spent parsing it.
  const JobCostCheck cost = check_job_cost(request, limits_, memory_budget_, scheduler_.threads());
  if (cost.verdict != JobCostCheck::Verdict::kFits) {
    spdlog::info("refused job '{}': {}", logged_name, cost.message);
    return grpc::Status(cost.verdict == JobCostCheck::Verdict::kOverMemoryBudget
                            ? grpc::StatusCode::RESOURCE_EXHAUSTED
                            : grpc::StatusCode::INVALID_ARGUMENT,
                        cost.message);
  }
  SceneConversion conversion = scene_from_proto(request.scene(), request.settings(), limits_);
  if (!conversion.ok()) {
    const std::string message = describe_issues(conversion.issues);
    spdlog::info("rejected job '{}': {}", logged_name, escape_client_text(message, 1024));
    return invalid(message);
  }
  const RenderSettings settings = conversion.scene->render;
  // Store tiles: every pass of every tile (job_passes.hpp).
  const auto tiles = PassLayout(settings).units();
  // The scene is read back from the store when the job is prepared; this copy is not kept.
  conversion.scene.reset();

  // A client that gave up while its scene was checked must not find a job it never heard
  // of running anyway: past this point the job exists. With a request id the job is stored
  // all the same: the client retries with the id and is given this job, and a job that
  // exists once is better than a retry that can never succeed because each attempt's scene
  // outlasts its deadline.
  const bool idempotent = !request.request_id().empty();
  if (!idempotent && context.IsCancelled())
    return grpc::Status(grpc::StatusCode::CANCELLED, "the call was cancelled; no job was created");
  if (!idempotent && context.deadline() <= std::chrono::system_clock::now())
    return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED,
                        "the call's deadline passed; no job was created");

  JobRecord record;
  record.name = request.name();
  record.submitter = submitter;
  record.request_id = request.request_id();
  record.request_fingerprint = fingerprint;
  record.priority = request.priority();
  record.settings = settings;
  record.tiles_total = static_cast<std::uint32_t>(tiles);
  record.submitted_unix_ms = unix_millis_now();
  record.labels = labels;
  SceneSource source;
  source.scene_proto = request.scene().SerializeAsString();
  source.settings_proto = settings_to_proto(settings).SerializeAsString();
  std::shared_ptr<Job> job;
  for (int attempt = 0; !job; ++attempt) {
    record.id = ids_.next();
    try {
      job = jobs_.create(record, source, max_jobs_per_submitter_);
    } catch (const DuplicateJobId&) {
      if (attempt == 3) throw;  // ids from an earlier run collided: try fresh ones
    } catch (const RequestIdTaken& e) {
      // An attempt of the same request stored its job while this one checked the scene.
      return answer_retry(caller, e.existing(), fingerprint, response);
    } catch (const SubmitterQuotaExceeded& e) {
      spdlog::info("refused job '{}' of '{}': {}", logged_name,
                   escape_client_text(record.submitter), e.what());
      return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                          "submitter '" + escape_client_text(record.submitter) + "': " + e.what());
    }
  }
  // Storing a large scene takes time too: a client whose call ended meanwhile was told no
  // job exists, so the job is withdrawn before any worker can see it. Not with a request
  // id: another attempt of the request may already have been given this job.
  if (!idempotent &&
      (context.IsCancelled() || context.deadline() <= std::chrono::system_clock::now())) {
    job->cancel("the SubmitJob call ended before the job was accepted");
    const JobRecord last = job->record();
    if (jobs_.store().delete_job(job->id())) {
      jobs_.forget(job->id());
      if (watch_hub_) watch_hub_->job_deleted(last);
    }
    return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED,
                        "the call ended while the job was stored; no job was created");
  }
  // The response describes the job as submitted (QUEUED), before a worker can pick it up.
  job_info_to_proto(job->info(), *response.mutable_job());
  // Logged before the scheduler has the job, so "submitted" always comes before the
  // "started" a worker logs. The feature summary (with light count) is logged once the
  // scene is prepared.
  log_event(
      spdlog::level::info, "job_submitted",
      {{"job_id", job->id()},
       {"name", record.name},
       {"submitter", record.submitter},
       {"priority", static_cast<std::int64_t>(job->priority())},
       {"width", static_cast<std::uint64_t>(settings.width)},
       {"height", static_cast<std::uint64_t>(settings.height)},
       {"samples_per_pixel", static_cast<std::uint64_t>(settings.samples_per_pixel)},
       {"passes", static_cast<std::uint64_t>(settings.pass_count())},
       {"tiles", static_cast<std::uint64_t>(tiles)}},
      fmt::format("job {} '{}' submitted by '{}': priority {}, {}x{}, {} spp in {} passes, "
                  "depth {}, {} tile passes",
                  job->id(), logged_name, escape_client_text(record.submitter), job->priority(),
                  settings.width, settings.height, settings.samples_per_pixel,
                  settings.pass_count(), settings.max_depth, tiles));
  if (!scheduler_.submit(job))
    // Stored, so not lost: the next start of the daemon runs it.
    spdlog::info("job {} stored while the daemon stops; it runs after a restart", job->id());
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::answer_retry(const Caller& caller, const JobRecord& existing,
                                             const std::string& fingerprint,
                                             v1::SubmitJobResponse& response) {
  // ALREADY_EXISTS rather than FAILED_PRECONDITION: what the request would create (a job
  // under this request id) exists, and no change of the daemon's state makes the request
  // valid; the client must choose another id. Retrying clients stop on it.
  if (existing.request_fingerprint != fingerprint)
    return grpc::Status(grpc::StatusCode::ALREADY_EXISTS,
                        "request_id: '" + existing.request_id + "' already created job " +
                            existing.id +
                            " with a different scene or settings; use a new request id");
  grpc::Status status;
  const auto job = find_job(existing.id, caller, status);
  if (!job) return status;  // deleted since it was found
  job_info_to_proto(job->info(), *response.mutable_job());
  spdlog::info("job {} returned again for request id '{}' of '{}' (a retry; no job created)",
               job->id(), existing.request_id, escape_client_text(existing.submitter));
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedStreamTiles(
    grpc::ServerContext* context,
    grpc::ServerSplitStreamer<v1::StreamTilesRequest, v1::Tile>* streamer) {
  {
    std::lock_guard lock(streams_mutex_);
    ++active_streams_;
  }
  struct StreamEnd {
    RenderServiceImpl& service;
    ~StreamEnd() {
      std::lock_guard lock(service.streams_mutex_);
      if (--service.active_streams_ == 0) service.streams_ended_.notify_all();
    }
  } stream_end{*this};
  const auto caller = rpc::authenticate("StreamTiles", access_, *context);
  if (const auto* refused = std::get_if<grpc::Status>(&caller)) return *refused;
  v1::StreamTilesRequest request;
  if (!streamer->Read(&request))
    return invalid("request: not a valid tessera.v1.StreamTilesRequest message");
  return guarded("StreamTiles",
                 [&] { return stream(*context, std::get<Caller>(caller), request, *streamer); });
}

grpc::Status RenderServiceImpl::stream(
    grpc::ServerContext& context, const Caller& caller, const v1::StreamTilesRequest& request,
    grpc::ServerSplitStreamer<v1::StreamTilesRequest, v1::Tile>& writer) {
  grpc::Status status;
  const auto job = find_job(request.job_id(), caller, status);
  if (!job) return status;
  const std::uint32_t tiles_total = job->record().tiles_total;
  if (request.after_sequence() > tiles_total)
    return invalid("after_sequence: must be at most the job's " + std::to_string(tiles_total) +
                   " deliveries, got " + std::to_string(request.after_sequence()));
  if (request.after_sequence() == 0 && request.after_tiles() > tiles_total)
    return invalid("after_tiles: must be at most the job's " + std::to_string(tiles_total) +
                   " tiles, got " + std::to_string(request.after_tiles()));
  // Deliveries are numbered by completion order in the store (the sequence), so
  // re-attaching is resuming there.
  std::uint32_t sent = request.after_sequence() != 0
                           ? static_cast<std::uint32_t>(request.after_sequence())
                           : request.after_tiles();
  v1::Tile message;
  for (;;) {
    if (context.IsCancelled())
      return grpc::Status(grpc::StatusCode::CANCELLED, "the client cancelled the stream");
    const TileUpdate update = job->wait_for_tiles(sent, poll_interval_);
    while (sent < update.tiles_done) {
      const std::vector<StoredTile> tiles = job->tiles_after(sent, kTilesPerRead);
      if (tiles.empty())  // deleted (DeleteJob or retention) while this stream read it
        return grpc::Status(grpc::StatusCode::NOT_FOUND,
                            "job " + job->id() + " was deleted while its tiles were streamed");
      const JobRecord record = job->record();
      for (const StoredTile& tile : tiles) {
        message.Clear();
        stored_tile_to_proto(record, tile, message);
        // A client that does not read blocks Write once flow control fills its window; the
        // watchdog ends the call after stream_write_timeout so this thread is not held. The
        // store keeps the tiles, so the stream itself buffers at most one read batch.
        const auto outcome = write_watchdog_.write(context, [&] { return writer.Write(message); });
        if (outcome == StreamWriteWatchdog::Outcome::kTimedOut) {
          spdlog::info(
              "stream of job {} ended: the client took no tile for {} ms (sent up to "
              "sequence {})",
              job->id(), write_watchdog_.timeout().count(), sent);
          return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED,
                              "the client read no tile for " +
                                  std::to_string(write_watchdog_.timeout().count()) +
                                  " ms; re-attach with after_sequence " + std::to_string(sent));
        }
        if (outcome == StreamWriteWatchdog::Outcome::kFailed)
          return grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
        sent = tile.ordinal;
      }
    }
    if (!update.finished) {
      if (!accepting_) {
        // Tells a client that re-attaching later is worth it (tessera_client's
        // kJobResumesMetadataKey; the server does not depend on the client library).
        context.AddTrailingMetadata("tessera-job-resumes", "1");
        return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                            "the daemon is shutting down; job " + job->id() +
                                " is kept and resumes when it restarts");
      }
      continue;
    }
    // A finished job gains no tiles, so every one has been sent.
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

int RenderServiceImpl::open_streams() const {
  std::lock_guard lock(streams_mutex_);
  return active_streams_;
}

bool RenderServiceImpl::wait_for_streams(std::chrono::milliseconds timeout) {
  std::unique_lock lock(streams_mutex_);
  return streams_ended_.wait_for(lock, timeout, [&] { return active_streams_ == 0; });
}

grpc::Status RenderServiceImpl::StreamedGetJob(
    grpc::ServerContext* context, grpc::ServerUnaryStreamer<v1::GetJobRequest, v1::Job>* streamer) {
  return unary("GetJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, v1::Job& response) {
                 grpc::Status status;
                 const auto job = find_job(request.job_id(), caller, status);
                 if (job) job_info_to_proto(job->info(), response);
                 return status;
               });
}

grpc::Status RenderServiceImpl::StreamedGetServerInfo(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::GetServerInfoRequest, v1::ServerInfo>* streamer) {
  // Like every RenderService call it needs a token when tokens are configured: the limits
  // and build it describes are not for anyone who can reach the port.
  return unary("GetServerInfo", access_, *context, *streamer,
               [&](const Caller&, const auto&, v1::ServerInfo& response) {
                 response = server_info_;
                 return grpc::Status::OK;
               });
}

grpc::Status RenderServiceImpl::StreamedListJobs(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::ListJobsRequest, v1::ListJobsResponse>* streamer) {
  return unary("ListJobs", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return list(caller, request, response);
               });
}

grpc::Status RenderServiceImpl::list(const Caller& caller, const v1::ListJobsRequest& request,
                                     v1::ListJobsResponse& response) {
  JobQuery query;
  // Larger pages are served at the maximum, as the API guidelines (AIP-158) suggest.
  query.limit =
      request.page_size() == 0 ? kDefaultPageSize : std::min(request.page_size(), kMaxPageSize);
  if (!request.page_token().empty()) {
    // The token is the sequence of the last job of the previous page.
    const std::string& token = request.page_token();
    std::int64_t sequence = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), sequence);
    if (error != std::errc() || end != token.data() + token.size() || sequence <= 0)
      return invalid("page_token: not a token this server issued");
    query.before_sequence = sequence;
  }
  if (!request.submitter().empty()) query.submitter = request.submitter();
  // A submit token lists its own jobs: another submitter's are refused, not shown empty,
  // so a script learns why it sees nothing.
  if (caller.restricted) {
    if (query.submitter && !caller.may_act_on(*query.submitter))
      return permission_denied("submitter: token '" + caller.name +
                               "' may list only its own jobs (submitter '" + caller.name + "')");
    query.submitter = caller.name;
  }
  if (request.name().size() > kMaxJobNameLength)
    return invalid("name: must be at most " + std::to_string(kMaxJobNameLength) + " bytes, got " +
                   std::to_string(request.name().size()));
  if (!request.name().empty()) query.name = request.name();
  if (!request.label().empty()) {
    std::string problem;
    const auto filter = parse_label_filter(request.label(), "label", problem);
    if (!filter) return invalid(problem);
    query.label_key = filter->key;
    query.label_value = filter->value;
  }
  if (request.state() != v1::JOB_STATE_UNSPECIFIED) {
    query.state = job_state_from_proto(request.state());
    if (!query.state) return invalid("state: unknown job state " + std::to_string(request.state()));
  }
  const std::size_t page = query.limit;
  ++query.limit;  // one more tells whether there is a next page
  std::vector<JobRecord> records = jobs_.store().list_jobs(query);
  const bool more = records.size() > page;
  if (more) records.resize(page);
  const std::int64_t now = unix_millis_now();
  for (const JobRecord& record : records)
    job_info_to_proto(job_info(record, now), *response.add_jobs());
  if (more) response.set_next_page_token(std::to_string(records.back().sequence));
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedCancelJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::CancelJobRequest, v1::CancelJobResponse>* streamer) {
  return unary("CancelJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return cancel(caller, request.job_id(), response);
               });
}

grpc::Status RenderServiceImpl::cancel(const Caller& caller, const std::string& job_id,
                                       v1::CancelJobResponse& response) {
  grpc::Status status;
  const auto job = find_job(job_id, caller, status);
  if (!job) return status;
  const CancelResult result = job->cancel("requested by a client");
  const JobInfo info = job->info();
  if (result == CancelResult::kAlreadyFinished)
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "job " + job->id() + " has already " + to_string(info.state));
  if (result == CancelResult::kCancelled) {
    scheduler_.job_changed();
    // A paused job has no scheduler entry to release it: let go of it here (a running
    // one is released again, harmlessly, once its tiles in flight return).
    jobs_.forget(job->id());
    spdlog::info("job {} cancelled by a client after {}/{} tiles", job->id(),
                 info.progress.tiles_done, info.progress.tiles_total);
  }
  job_info_to_proto(info, *response.mutable_job());
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedDeleteJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::DeleteJobRequest, v1::DeleteJobResponse>* streamer) {
  return unary("DeleteJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto&) {
                 return remove(caller, request.job_id());
               });
}

grpc::Status RenderServiceImpl::remove(const Caller& caller, const std::string& job_id) {
  grpc::Status status;
  const auto job = find_job(job_id, caller, status);
  if (!job) return status;
  if (!job->finished())
    return grpc::Status(
        grpc::StatusCode::FAILED_PRECONDITION,
        "job " + job->id() + " is " + to_string(job->state()) + "; cancel it before deleting it");
  const JobRecord last = job->record();
  if (!jobs_.store().delete_job(job->id()))
    return grpc::Status(grpc::StatusCode::NOT_FOUND, "job '" + job->id() + "' not found");
  jobs_.forget(job->id());
  if (watch_hub_) watch_hub_->job_deleted(last);
  spdlog::info("job {} deleted by a client", job->id());
  return grpc::Status::OK;
}

}  // namespace tessera::server
