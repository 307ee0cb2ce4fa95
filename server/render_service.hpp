#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>

#include "server/access_control.hpp"
#include "server/job_id.hpp"
#include "server/job_registry.hpp"
#include "server/job_watch.hpp"
#include "server/scheduler.hpp"
#include "server/stream_write_watchdog.hpp"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera::server {

// Longest job id a request may name; ids this daemon makes are 16 bytes.
inline constexpr std::size_t kMaxJobIdLength = 64;
inline constexpr std::size_t kMaxJobNameLength = 256;
inline constexpr std::size_t kMaxSubmitterLength = 128;
inline constexpr std::uint32_t kDefaultPageSize = 100;
inline constexpr std::uint32_t kMaxPageSize = 1000;

// tessera.v1.RenderService on the synchronous gRPC API: requests are validated and turned
// into jobs in the store and the scheduler; StreamTiles reads tiles from the store as the
// job stores them (a batch at a time, so a slow client only falls behind), checking between
// waits whether its client is still there, and gives each write stream_write_timeout
// (StreamWriteWatchdog) before it ends a call whose client does not read.
//
// Every method is registered in its "streamed" form, where the handler reads the request
// itself: that way a request whose bytes are not a valid message is answered with
// INVALID_ARGUMENT (the plain form lets gRPC answer INTERNAL with an empty message).
class RenderServiceImpl final : public v1::RenderService::StreamedService {
 public:
  // `max_jobs_per_submitter`: queued and running jobs one submitter may have (0: no limit).
  RenderServiceImpl(JobRegistry& jobs, Scheduler& scheduler, SceneLimits limits,
                    std::size_t max_jobs_per_submitter = 0,
                    std::chrono::milliseconds poll_interval = std::chrono::milliseconds(100),
                    std::chrono::milliseconds stream_write_timeout = std::chrono::seconds(30));

  grpc::Status StreamedSubmitJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::SubmitJobRequest, v1::SubmitJobResponse>* streamer) override;
  grpc::Status StreamedStreamTiles(
      grpc::ServerContext* context,
      grpc::ServerSplitStreamer<v1::StreamTilesRequest, v1::Tile>* streamer) override;
  grpc::Status StreamedGetJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::GetJobRequest, v1::Job>* streamer) override;
  grpc::Status StreamedListJobs(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::ListJobsRequest, v1::ListJobsResponse>* streamer) override;
  grpc::Status StreamedCancelJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::CancelJobRequest, v1::CancelJobResponse>* streamer) override;
  grpc::Status StreamedDeleteJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::DeleteJobRequest, v1::DeleteJobResponse>* streamer) override;

  grpc::Status StreamedGetServerInfo(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::GetServerInfoRequest, v1::ServerInfo>* streamer) override;
  // What GetServerInfo answers (server_info.hpp). Call before serving.
  void set_server_info(v1::ServerInfo info) { server_info_ = std::move(info); }

  // A job whose estimated memory (server/job_cost.hpp) exceeds `bytes` is refused with
  // RESOURCE_EXHAUSTED before its scene is converted; 0 (the default): no limit. Call
  // before serving.
  void set_memory_budget(std::size_t bytes) { memory_budget_ = bytes; }
  // Job control and WatchJobs (render_service_control.cpp).
  grpc::Status StreamedPauseJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::PauseJobRequest, v1::PauseJobResponse>* streamer) override;
  grpc::Status StreamedResumeJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::ResumeJobRequest, v1::ResumeJobResponse>* streamer) override;
  grpc::Status StreamedRetryJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::RetryJobRequest, v1::RetryJobResponse>* streamer) override;
  grpc::Status StreamedUpdateJob(
      grpc::ServerContext* context,
      grpc::ServerUnaryStreamer<v1::UpdateJobRequest, v1::UpdateJobResponse>* streamer) override;
  grpc::Status StreamedWatchJobs(
      grpc::ServerContext* context,
      grpc::ServerSplitStreamer<v1::WatchJobsRequest, v1::JobEvent>* streamer) override;

  // Who may call, and which jobs each caller sees (access_control.hpp); the default lets
  // everyone do everything. Call before the server starts.
  void set_access_control(AccessControl access) { access_ = std::move(access); }

  // WatchJobs reads job changes from `hub` (the registry's listener); without one it
  // answers UNIMPLEMENTED. Call before the server starts.
  void enable_watch(JobWatchHub& hub) { watch_hub_ = &hub; }

  // From now on SubmitJob answers UNAVAILABLE, and streams of unfinished jobs end with
  // UNAVAILABLE (their jobs resume when the daemon restarts).
  void stop_accepting() { accepting_ = false; }

  // After stop_accepting(): waits up to `timeout` for every StreamTiles call to have
  // returned, so each ends with its own status (UNAVAILABLE and the resume hint) rather
  // than being cut off by the server's shutdown. Returns false on timeout.
  bool wait_for_streams(std::chrono::milliseconds timeout);

  // StreamTiles calls open now, and those ended because a write waited longer than the
  // stream write timeout for a client that did not read.
  int open_streams() const;
  std::uint64_t stream_write_timeouts() const { return write_watchdog_.timeouts(); }

 private:
  // Each takes the authenticated caller (rpc::unary, rpc::authenticate): a restricted one
  // reaches only its own jobs.
  grpc::Status submit(grpc::ServerContext& context, const Caller& caller,
                      const v1::SubmitJobRequest& request, v1::SubmitJobResponse& response);
  // SubmitJob of a request id that already created `existing`: that job when `fingerprint`
  // (the request's scene and settings) is the one it was created with, ALREADY_EXISTS if not.
  grpc::Status answer_retry(const Caller& caller, const JobRecord& existing,
                            const std::string& fingerprint, v1::SubmitJobResponse& response);
  grpc::Status stream(grpc::ServerContext& context, const Caller& caller,
                      const v1::StreamTilesRequest& request,
                      grpc::ServerSplitStreamer<v1::StreamTilesRequest, v1::Tile>& writer);
  grpc::Status list(const Caller& caller, const v1::ListJobsRequest& request,
                    v1::ListJobsResponse& response);
  grpc::Status cancel(const Caller& caller, const std::string& job_id,
                      v1::CancelJobResponse& response);
  grpc::Status remove(const Caller& caller, const std::string& job_id);
  grpc::Status pause(const Caller& caller, const std::string& job_id, v1::Job& out);
  grpc::Status resume(const Caller& caller, const std::string& job_id, v1::Job& out);
  grpc::Status retry(const Caller& caller, const std::string& job_id, v1::Job& out);
  grpc::Status update(const Caller& caller, const v1::UpdateJobRequest& request, v1::Job& out);
  grpc::Status watch(grpc::ServerContext& context, const Caller& caller,
                     const v1::WatchJobsRequest& request,
                     grpc::ServerSplitStreamer<v1::WatchJobsRequest, v1::JobEvent>& writer);
  // RESOURCE_EXHAUSTED when one more unfinished job of `submitter` would pass the cap
  // (RetryJob, and UpdateJob moving an unfinished job to another submitter).
  std::optional<grpc::Status> submitter_quota(const std::string& submitter);
  // Counts a streaming call for wait_for_streams while it lives.
  class StreamScope;
  // The job, or the status to answer when `job_id` is empty, too long or unknown, or
  // PERMISSION_DENIED when the job is not the caller's to see.
  std::shared_ptr<Job> find_job(const std::string& job_id, const Caller& caller,
                                grpc::Status& status) const;

  JobRegistry& jobs_;
  Scheduler& scheduler_;
  SceneLimits limits_;
  std::size_t max_jobs_per_submitter_;
  std::size_t memory_budget_ = 0;
  std::chrono::milliseconds poll_interval_;
  JobIdGenerator ids_;
  std::atomic<bool> accepting_{true};
  StreamWriteWatchdog write_watchdog_;
  mutable std::mutex streams_mutex_;
  std::condition_variable streams_ended_;
  int active_streams_ = 0;
  JobWatchHub* watch_hub_ = nullptr;
  v1::ServerInfo server_info_;
  AccessControl access_;
};

}  // namespace tessera::server
