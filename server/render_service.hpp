#pragma once
#include <atomic>
#include <chrono>

#include "server/job_id.hpp"
#include "server/job_store.hpp"
#include "server/scheduler.hpp"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera::server {

// tessera.v1.RenderService on the synchronous gRPC API: requests are validated and turned
// into jobs for the scheduler; StreamTiles waits on the job for tiles, checking between
// waits whether its client is still there.
class RenderServiceImpl final : public v1::RenderService::Service {
 public:
  RenderServiceImpl(JobStore& store, Scheduler& scheduler, SceneLimits limits,
                    std::chrono::milliseconds poll_interval = std::chrono::milliseconds(100));

  grpc::Status SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                         v1::SubmitJobResponse* response) override;
  grpc::Status StreamTiles(grpc::ServerContext* context, const v1::StreamTilesRequest* request,
                           grpc::ServerWriter<v1::Tile>* writer) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                      v1::Job* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                         v1::CancelJobResponse* response) override;

  // From now on SubmitJob answers UNAVAILABLE.
  void stop_accepting() { accepting_ = false; }

 private:
  grpc::Status submit(const v1::SubmitJobRequest& request, v1::SubmitJobResponse& response);
  grpc::Status stream(grpc::ServerContext& context, const std::string& job_id,
                      grpc::ServerWriter<v1::Tile>& writer);
  grpc::Status cancel(const std::string& job_id, v1::CancelJobResponse& response);
  // The job, or the status to answer when `job_id` is empty or unknown.
  std::shared_ptr<Job> find_job(const std::string& job_id, grpc::Status& status) const;

  JobStore& store_;
  Scheduler& scheduler_;
  SceneLimits limits_;
  std::chrono::milliseconds poll_interval_;
  JobIdGenerator ids_;
  std::atomic<bool> accepting_{true};
};

}  // namespace tessera::server
