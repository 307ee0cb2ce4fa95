#include "client/client.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

namespace tessera {

namespace {

// The largest tile (1024 x 1024 RGBA float) is 16 MiB before compression; noise can make
// EXR's zip output slightly larger than its input.
constexpr int kMaxReceiveBytes = 64 * 1024 * 1024;

void set_deadline(grpc::ClientContext& context, std::chrono::milliseconds timeout) {
  context.set_deadline(std::chrono::system_clock::now() + timeout);
}

void check(const grpc::Status& status) {
  if (!status.ok()) throw ClientError::from_status(status);
}

}  // namespace

std::shared_ptr<grpc::Channel> make_channel(const std::string& target) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(kMaxReceiveBytes);
  args.SetMaxSendMessageSize(-1);
  return grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args);
}

Client::Client(ClientOptions options) : Client(make_channel(options.target), options) {}

Client::Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options)
    : options_(std::move(options)),
      channel_(std::move(channel)),
      stub_(v1::RenderService::NewStub(channel_)) {}

Client::~Client() = default;

v1::Job Client::submit(const v1::SubmitJobRequest& request) {
  grpc::ClientContext context;
  set_deadline(context, options_.submit_deadline);
  v1::SubmitJobResponse response;
  check(stub_->SubmitJob(&context, request, &response));
  return response.job();
}

void Client::stream_tiles(const std::string& job_id, const TileCallback& on_tile) {
  // No deadline: a render may legitimately run for hours.
  grpc::ClientContext context;
  v1::StreamTilesRequest request;
  request.set_job_id(job_id);
  std::unique_ptr<grpc::ClientReader<v1::Tile>> reader = stub_->StreamTiles(&context, request);
  v1::Tile tile;
  try {
    while (reader->Read(&tile)) on_tile(tile);
  } catch (...) {
    context.TryCancel();
    reader->Finish();
    throw;
  }
  check(reader->Finish());
}

v1::Job Client::get(const std::string& job_id) {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  v1::Job job;
  check(stub_->GetJob(&context, request, &job));
  return job;
}

v1::ListJobsResponse Client::list_page(const v1::ListJobsRequest& request) {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::ListJobsResponse response;
  check(stub_->ListJobs(&context, request, &response));
  return response;
}

std::vector<v1::Job> Client::list() {
  std::vector<v1::Job> jobs;
  v1::ListJobsRequest request;
  for (;;) {
    const v1::ListJobsResponse page = list_page(request);
    jobs.insert(jobs.end(), page.jobs().begin(), page.jobs().end());
    if (page.next_page_token().empty()) return jobs;
    request.set_page_token(page.next_page_token());
  }
}

void Client::remove(const std::string& job_id) {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::DeleteJobRequest request;
  request.set_job_id(job_id);
  v1::DeleteJobResponse response;
  check(stub_->DeleteJob(&context, request, &response));
}

v1::Job Client::cancel(const std::string& job_id) {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::CancelJobRequest request;
  request.set_job_id(job_id);
  v1::CancelJobResponse response;
  check(stub_->CancelJob(&context, request, &response));
  return response.job();
}

}  // namespace tessera
