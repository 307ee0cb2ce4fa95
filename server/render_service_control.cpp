// RenderService's job control (PauseJob, ResumeJob, RetryJob, UpdateJob) and WatchJobs.
#include <spdlog/spdlog.h>

#include "server/job_labels.hpp"
#include "server/job_proto.hpp"
#include "server/log_text.hpp"
#include "server/render_service.hpp"
#include "server/rpc_handler.hpp"

namespace tessera::server {

using rpc::guarded;
using rpc::invalid;
using rpc::permission_denied;
using rpc::unary;

namespace {

grpc::Status failed_precondition(std::string message) {
  return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, std::move(message));
}

}  // namespace

class RenderServiceImpl::StreamScope {
 public:
  explicit StreamScope(RenderServiceImpl& service) : service_(service) {
    std::lock_guard lock(service_.streams_mutex_);
    ++service_.active_streams_;
  }
  ~StreamScope() {
    std::lock_guard lock(service_.streams_mutex_);
    if (--service_.active_streams_ == 0) service_.streams_ended_.notify_all();
  }
  StreamScope(const StreamScope&) = delete;
  StreamScope& operator=(const StreamScope&) = delete;

 private:
  RenderServiceImpl& service_;
};

std::optional<grpc::Status> RenderServiceImpl::submitter_quota(const std::string& submitter) {
  if (max_jobs_per_submitter_ == 0) return std::nullopt;
  const std::size_t unfinished = jobs_.store().unfinished_count(submitter);
  if (unfinished < max_jobs_per_submitter_) return std::nullopt;
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "submitter '" + escape_client_text(submitter) + "' already has " +
                          std::to_string(unfinished) +
                          " queued, running or paused jobs, the most this daemon accepts "
                          "(max_jobs_per_submitter)");
}

grpc::Status RenderServiceImpl::StreamedPauseJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::PauseJobRequest, v1::PauseJobResponse>* streamer) {
  return unary("PauseJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return pause(caller, request.job_id(), *response.mutable_job());
               });
}

grpc::Status RenderServiceImpl::pause(const Caller& caller, const std::string& job_id,
                                      v1::Job& out) {
  grpc::Status status;
  const auto job = find_job(job_id, caller, status);
  if (!job) return status;
  const ControlResult result = job->pause();
  if (result == ControlResult::kRefused)
    return failed_precondition("job " + job->id() + " has already " + to_string(job->state()) +
                               "; only queued or running jobs can be paused");
  if (result == ControlResult::kDone) {
    scheduler_.job_changed();
    spdlog::info("job {} paused by a client", job->id());
  }
  job_info_to_proto(job->info(), out);
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedResumeJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::ResumeJobRequest, v1::ResumeJobResponse>* streamer) {
  return unary("ResumeJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return resume(caller, request.job_id(), *response.mutable_job());
               });
}

grpc::Status RenderServiceImpl::resume(const Caller& caller, const std::string& job_id,
                                       v1::Job& out) {
  grpc::Status status;
  const auto job = find_job(job_id, caller, status);
  if (!job) return status;
  const ControlResult result = job->resume();
  if (result == ControlResult::kRefused)
    return failed_precondition("job " + job->id() + " has already " + to_string(job->state()) +
                               "; only a paused job can be resumed");
  // The response describes the job as resumed (QUEUED), before a worker picks it up.
  const JobInfo info = job->info();
  if (result == ControlResult::kDone) {
    if (!scheduler_.requeue(job))
      spdlog::info("job {} resumed while the daemon stops; it runs after a restart", job->id());
    else
      spdlog::info("job {} resumed by a client", job->id());
  }
  job_info_to_proto(info, out);
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedRetryJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::RetryJobRequest, v1::RetryJobResponse>* streamer) {
  return unary("RetryJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return retry(caller, request.job_id(), *response.mutable_job());
               });
}

grpc::Status RenderServiceImpl::retry(const Caller& caller, const std::string& job_id,
                                      v1::Job& out) {
  grpc::Status status;
  const auto found = find_job(job_id, caller, status);
  if (!found) return status;  // empty, too long or unknown
  if (!accepting_)
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
  // A retried job is unfinished again, so it counts against its submitter's cap.
  if (is_finished(found->state()))
    if (auto refused = submitter_quota(found->submitter())) return *refused;
  ControlResult result = ControlResult::kRefused;
  const auto job = jobs_.retry(job_id, result);
  if (!job)
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        "job '" + escape_client_text(job_id) + "' not found");
  if (result != ControlResult::kDone)
    return failed_precondition("job " + job->id() + " is " + to_string(job->state()) +
                               "; only failed or cancelled jobs can be retried");
  const JobInfo info = job->info();
  if (!scheduler_.requeue(job))
    spdlog::info("job {} retried while the daemon stops; it runs after a restart", job->id());
  else
    spdlog::info("job {} retried by a client: {}/{} tiles kept", job->id(),
                 info.progress.tiles_done, info.progress.tiles_total);
  job_info_to_proto(info, out);
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedUpdateJob(
    grpc::ServerContext* context,
    grpc::ServerUnaryStreamer<v1::UpdateJobRequest, v1::UpdateJobResponse>* streamer) {
  return unary("UpdateJob", access_, *context, *streamer,
               [&](const Caller& caller, const auto& request, auto& response) {
                 return update(caller, request, *response.mutable_job());
               });
}

grpc::Status RenderServiceImpl::update(const Caller& caller, const v1::UpdateJobRequest& request,
                                       v1::Job& out) {
  JobUpdate change;
  if (request.has_priority()) change.priority = request.priority();
  if (request.has_submitter()) {
    const std::string& submitter = request.submitter();
    if (submitter.empty()) return invalid("submitter: must not be empty when set");
    if (submitter.size() > kMaxSubmitterLength)
      return invalid("submitter: must be at most " + std::to_string(kMaxSubmitterLength) +
                     " bytes, got " + std::to_string(submitter.size()));
    change.submitter = submitter;
  }
  if (request.remove_labels_size() > static_cast<int>(kMaxLabels))
    return invalid("remove_labels: at most " + std::to_string(kMaxLabels) + " keys, got " +
                   std::to_string(request.remove_labels_size()));
  for (const std::string& key : request.remove_labels()) {
    if (const auto problem = label_key_problem(key))
      return invalid("remove_labels: key '" + escape_client_text(key, 80) + "' " + *problem);
    change.remove_labels.push_back(key);
  }
  change.set_labels = JobLabels(request.set_labels().begin(), request.set_labels().end());
  if (const auto problem = labels_problem(change.set_labels, "set_labels"))
    return invalid(*problem);

  grpc::Status status;
  const auto job = find_job(request.job_id(), caller, status);
  if (!job) return status;
  // Handing a job to another submitter would charge their cap and hide it from its owner.
  if (change.submitter && !caller.may_act_on(*change.submitter))
    return permission_denied("submitter: only an admin token may give a job to another submitter");
  JobLabels labels = job->record().labels;
  for (const std::string& key : change.remove_labels) labels.erase(key);
  for (const auto& [key, value] : change.set_labels) labels[key] = value;
  if (labels.size() > kMaxLabels)
    return invalid("set_labels: the job would have " + std::to_string(labels.size()) +
                   " labels, more than " + std::to_string(kMaxLabels));
  if (change.submitter && !job->finished() && *change.submitter != job->submitter())
    if (auto refused = submitter_quota(*change.submitter)) return *refused;
  const int old_priority = job->priority();
  const JobInfo info = job->update(change);
  if (info.priority != old_priority) scheduler_.job_changed();
  spdlog::info("job {} updated by a client: priority {}, submitter '{}', {} labels", job->id(),
               info.priority, escape_client_text(info.submitter), info.labels.size());
  job_info_to_proto(info, out);
  return grpc::Status::OK;
}

grpc::Status RenderServiceImpl::StreamedWatchJobs(
    grpc::ServerContext* context,
    grpc::ServerSplitStreamer<v1::WatchJobsRequest, v1::JobEvent>* streamer) {
  const StreamScope scope(*this);
  const auto caller = rpc::authenticate("WatchJobs", access_, *context);
  if (const auto* refused = std::get_if<grpc::Status>(&caller)) return *refused;
  v1::WatchJobsRequest request;
  if (!streamer->Read(&request))
    return invalid("request: not a valid tessera.v1.WatchJobsRequest message");
  return guarded("WatchJobs",
                 [&] { return watch(*context, std::get<Caller>(caller), request, *streamer); });
}

grpc::Status RenderServiceImpl::watch(
    grpc::ServerContext& context, const Caller& caller, const v1::WatchJobsRequest& request,
    grpc::ServerSplitStreamer<v1::WatchJobsRequest, v1::JobEvent>& writer) {
  if (!watch_hub_)
    return grpc::Status(grpc::StatusCode::UNIMPLEMENTED, "this server does not watch jobs");
  if (!accepting_)
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
  WatchFilter filter;
  if (!request.job_id().empty()) {
    grpc::Status status;
    const auto job = find_job(request.job_id(), caller, status);
    if (!job) return status;
    filter.job_id = job->id();
  }
  if (request.submitter().size() > kMaxSubmitterLength)
    return invalid("submitter: must be at most " + std::to_string(kMaxSubmitterLength) +
                   " bytes, got " + std::to_string(request.submitter().size()));
  filter.submitter = request.submitter();
  // A submit token watches its own jobs only (as ListJobs lists them).
  if (caller.restricted) {
    if (!filter.submitter.empty() && !caller.may_act_on(filter.submitter))
      return permission_denied("submitter: token '" + caller.name +
                               "' may watch only its own jobs (submitter '" + caller.name + "')");
    filter.submitter = caller.name;
  }
  if (!request.label().empty()) {
    std::string problem;
    const auto label = parse_label_filter(request.label(), "label", problem);
    if (!label) return invalid(problem);
    filter.label_key = label->key;
    filter.label_value = label->value;
  }

  JobStore& store = jobs_.store();
  const auto snapshot = [&]() -> std::vector<JobRecord> {
    if (!filter.job_id.empty()) {
      auto job = store.find_job(filter.job_id);
      return job ? std::vector<JobRecord>{std::move(*job)} : std::vector<JobRecord>{};
    }
    return store.unfinished_jobs();
  };
  grpc::ServerContext* const call = &context;
  const auto watcher = watch_hub_->subscribe(filter, snapshot, [call] { call->TryCancel(); });
  struct Unsubscribe {
    JobWatchHub& hub;
    const std::shared_ptr<JobWatchHub::Watcher>& watcher;
    ~Unsubscribe() { hub.unsubscribe(watcher); }
  } unsubscribe{*watch_hub_, watcher};

  v1::JobEvent event;
  for (;;) {
    // Dropped first: the watchdog's cancel also makes the call look cancelled.
    switch (watcher->dropped()) {
      case WatchDrop::kBufferFull:
        spdlog::info("a watcher fell behind by {} events and was dropped",
                     watch_hub_->options().buffer_events);
        return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                            "the watcher fell behind by more than " +
                                std::to_string(watch_hub_->options().buffer_events) +
                                " events; watch again for a fresh snapshot");
      case WatchDrop::kWriteTimeout:
        spdlog::info("a watcher whose write waited longer than {} ms was dropped",
                     watch_hub_->options().write_timeout.count());
        return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED,
                            "a write to this watcher waited longer than the watch write timeout");
      case WatchDrop::kNone:
        break;
    }
    if (context.IsCancelled())
      return grpc::Status(grpc::StatusCode::CANCELLED, "the client cancelled the watch");
    if (!accepting_)
      return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the daemon is shutting down");
    const std::optional<JobChange> change = watcher->next(poll_interval_);
    if (watcher->dropped() != WatchDrop::kNone) continue;  // reported above
    if (!change) continue;
    event.Clear();
    // Jobs deleted by retention are known by their id alone (a real job has a tile).
    if (change->deleted && change->job.tiles_total == 0)
      event.mutable_job()->set_id(change->job.id);
    else
      job_info_to_proto(job_info(change->job, unix_millis_now()), *event.mutable_job());
    event.set_deleted(change->deleted);
    event.set_snapshot(change->snapshot);
    watcher->begin_write();
    const bool written = writer.Write(event);
    watcher->end_write();
    if (!written) {
      if (watcher->dropped() != WatchDrop::kNone) continue;  // reported at the loop's top
      return grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
    }
  }
}

}  // namespace tessera::server
