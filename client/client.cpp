#include "client/client.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>
#include <grpcpp/support/client_interceptor.h>

#include <algorithm>
#include <cstdio>
#include <future>
#include <random>
#include <thread>

namespace tessera {

namespace {

// The largest tile (1024 x 1024 RGBA float) is 16 MiB before compression; noise can make
// EXR's zip output slightly larger than its input.
constexpr int kMaxReceiveBytes = 64 * 1024 * 1024;

void set_deadline(grpc::ClientContext& context, std::chrono::milliseconds timeout) {
  context.set_deadline(std::chrono::system_clock::now() + timeout);
}

constexpr const char* kStreamStopped = "the stream was stopped by the caller";

void check(const grpc::Status& status) {
  if (!status.ok()) throw ClientError::from_status(status);
}

// Adds `authorization: Bearer <token>` to the initial metadata of every call.
class BearerTokenInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit BearerTokenInterceptor(std::string header) : header_(std::move(header)) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA))
      methods->GetSendInitialMetadata()->emplace("authorization", header_);
    methods->Proceed();
  }

 private:
  std::string header_;
};

class BearerTokenInterceptorFactory final
    : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit BearerTokenInterceptorFactory(std::string token) : header_("Bearer " + token) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(
      grpc::experimental::ClientRpcInfo*) override {
    return new BearerTokenInterceptor(header_);
  }

 private:
  std::string header_;
};

grpc::ChannelArguments channel_arguments() {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(kMaxReceiveBytes);
  args.SetMaxSendMessageSize(-1);
  return args;
}

}  // namespace

std::shared_ptr<grpc::Channel> make_channel(const std::string& target) {
  return grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), channel_arguments());
}

std::shared_ptr<grpc::Channel> make_channel(const ClientOptions& options) {
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (options.tls.enabled) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = options.tls.root_certs_pem;
    ssl.pem_cert_chain = options.tls.client_cert_pem;
    ssl.pem_private_key = options.tls.client_key_pem;
    credentials = grpc::SslCredentials(ssl);
  }
  std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> interceptors;
  if (!options.token.empty())
    interceptors.push_back(std::make_unique<BearerTokenInterceptorFactory>(options.token));
  return grpc::experimental::CreateCustomChannelWithInterceptors(
      options.target, credentials, channel_arguments(), std::move(interceptors));
}

Client::Client(ClientOptions options) : Client(make_channel(options), options) {}

Client::Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options)
    : options_(std::move(options)),
      channel_(std::move(channel)),
      stub_(v1::RenderService::NewStub(channel_)) {}

Client::~Client() = default;

std::string make_request_id() {
  std::random_device random;
  std::string id;
  for (int word = 0; word < 4; ++word) {
    char hex[9];
    std::snprintf(hex, sizeof hex, "%08x", static_cast<unsigned>(random()));
    id += hex;
  }
  return id;
}

v1::Job Client::submit(const v1::SubmitJobRequest& request) {
  const int attempts = request.request_id().empty() ? 1 : std::max(options_.submit_attempts, 1);
  auto pause = options_.submit_retry_pause;
  for (int attempt = 1;; ++attempt) {
    grpc::ClientContext context;
    set_deadline(context, options_.submit_deadline);
    v1::SubmitJobResponse response;
    const grpc::Status status = stub_->SubmitJob(&context, request, &response);
    const bool retryable = status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED ||
                           status.error_code() == grpc::StatusCode::UNAVAILABLE;
    if (status.ok() || !retryable || attempt >= attempts) {
      check(status);
      return response.job();
    }
    std::this_thread::sleep_for(pause);
    pause *= 2;
  }
}

void Client::stream_tiles(const std::string& job_id, const TileCallback& on_tile) {
  // Deliveries (tiles, or passes of tiles) come in the job's completion order and each
  // carries its place in it (sequence), so a broken stream re-attaches after the last one
  // received. A daemon from before sequences sends 0 there; its progress.tiles_done is the
  // same place, which after_tiles takes.
  std::uint64_t received = 0;
  bool by_sequence = true;
  auto give_up_at = std::chrono::steady_clock::now() + options_.reconnect_window;
  auto pause = std::chrono::milliseconds(200);
  bool daemon_stopping = false;  // a daemon said it stops, and none has streamed since
  for (;;) {
    // No deadline: a render may legitimately run for hours.
    grpc::ClientContext context;
    v1::StreamTilesRequest request;
    request.set_job_id(job_id);
    if (by_sequence)
      request.set_after_sequence(received);
    else
      request.set_after_tiles(static_cast<std::uint32_t>(received));
    {
      std::lock_guard lock(streams_mutex_);
      if (streams_stopped_) throw ClientError(grpc::StatusCode::CANCELLED, kStreamStopped);
      open_stream_ = &context;
    }
    struct Unregister {
      Client& client;
      ~Unregister() {
        std::lock_guard lock(client.streams_mutex_);
        client.open_stream_ = nullptr;
      }
    } unregister{*this};
    std::unique_ptr<grpc::ClientReader<v1::Tile>> reader = stub_->StreamTiles(&context, request);
    v1::Tile tile;
    try {
      while (reader->Read(&tile)) {
        on_tile(tile);
        by_sequence = tile.sequence() != 0;
        received = by_sequence ? tile.sequence() : tile.progress().tiles_done();
        daemon_stopping = false;
        give_up_at = std::chrono::steady_clock::now() + options_.reconnect_window;
        pause = std::chrono::milliseconds(200);
      }
    } catch (...) {
      context.TryCancel();
      reader->Finish();
      throw;
    }
    const grpc::Status status = reader->Finish();
    {
      std::lock_guard lock(streams_mutex_);
      if (streams_stopped_) throw ClientError(grpc::StatusCode::CANCELLED, kStreamStopped);
    }
    // Worth waiting for: a daemon that said it stops and keeps the job, or one that was
    // streaming this job until the connection broke. A call made while a daemon shuts down
    // may also be cut off with CANCELLED (not the job's own, which a re-attached stream
    // would report again). A daemon never reached, or any other end, is reported at once.
    const auto& trailers = context.GetServerTrailingMetadata();
    const bool job_kept = trailers.find(kJobResumesMetadataKey) != trailers.end();
    const bool retry = std::chrono::steady_clock::now() < give_up_at &&
                       ((status.error_code() == grpc::StatusCode::UNAVAILABLE &&
                         (job_kept || received > 0 || daemon_stopping)) ||
                        (status.error_code() == grpc::StatusCode::CANCELLED && daemon_stopping));
    if (!retry) return check(status);
    // Once told, the daemon is taken to be restarting until a stream gets through; a
    // CANCELLED is retried once, so a job really cancelled meanwhile is reported next time.
    if (job_kept)
      daemon_stopping = true;
    else if (status.error_code() == grpc::StatusCode::CANCELLED)
      daemon_stopping = false;
    // A stopping daemon takes a moment to go; asking again at once only finds it going.
    if (job_kept) pause = std::max(pause, std::chrono::milliseconds(1000));
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::milliseconds(2000));
  }
}

void Client::stop_streams() {
  std::lock_guard lock(streams_mutex_);
  streams_stopped_ = true;
  if (open_stream_) open_stream_->TryCancel();
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

std::vector<v1::Job> Client::list(v1::ListJobsRequest request) {
  std::vector<v1::Job> jobs;
  request.clear_page_token();
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

namespace {

// One unary job-control call naming a job; returns the job from its response.
template <typename Request, typename Response, typename Call>
v1::Job control(const std::string& job_id, std::chrono::milliseconds deadline, Call&& call) {
  grpc::ClientContext context;
  set_deadline(context, deadline);
  Request request;
  request.set_job_id(job_id);
  Response response;
  check(call(&context, request, &response));
  return response.job();
}

}  // namespace

v1::Job Client::pause(const std::string& job_id) {
  return control<v1::PauseJobRequest, v1::PauseJobResponse>(
      job_id, options_.unary_deadline, [&](auto* context, const auto& request, auto* response) {
        return stub_->PauseJob(context, request, response);
      });
}

v1::Job Client::resume(const std::string& job_id) {
  return control<v1::ResumeJobRequest, v1::ResumeJobResponse>(
      job_id, options_.unary_deadline, [&](auto* context, const auto& request, auto* response) {
        return stub_->ResumeJob(context, request, response);
      });
}

v1::Job Client::retry(const std::string& job_id) {
  return control<v1::RetryJobRequest, v1::RetryJobResponse>(
      job_id, options_.unary_deadline, [&](auto* context, const auto& request, auto* response) {
        return stub_->RetryJob(context, request, response);
      });
}

v1::Job Client::update(const v1::UpdateJobRequest& request) {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::UpdateJobResponse response;
  check(stub_->UpdateJob(&context, request, &response));
  return response.job();
}

v1::ServerInfo Client::server_info() {
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  v1::ServerInfo info;
  check(stub_->GetServerInfo(&context, v1::GetServerInfoRequest(), &info));
  return info;
}

bool Client::healthy() {
  // grpc.health.v1 by hand (a generic call): Debian ships no generated health stubs, and
  // the two messages are one field each. HealthCheckRequest{service = field 1, string}.
  const std::string service = "tessera.v1.RenderService";
  std::string request_bytes = std::string("\x0a", 1) + static_cast<char>(service.size()) + service;
  grpc::GenericStub generic(channel_);
  grpc::ClientContext context;
  set_deadline(context, options_.unary_deadline);
  grpc::Slice slice(request_bytes);
  grpc::ByteBuffer request(&slice, 1);
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  generic.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request,
                    &response, [&](grpc::Status status) { done.set_value(std::move(status)); });
  check(done.get_future().get());
  std::vector<grpc::Slice> slices;
  if (!response.Dump(&slices).ok())
    throw ClientError(grpc::StatusCode::INTERNAL, "unreadable health check response");
  std::string bytes;
  for (const grpc::Slice& part : slices)
    bytes.append(reinterpret_cast<const char*>(part.begin()), part.size());
  // HealthCheckResponse{status = field 1, enum}: SERVING is 1.
  return bytes == std::string("\x08\x01", 2);
}

void Client::watch_jobs(const v1::WatchJobsRequest& request, const JobEventCallback& on_event) {
  // No deadline: a watch lasts as long as its caller wants.
  grpc::ClientContext context;
  const auto reader = stub_->WatchJobs(&context, request);
  v1::JobEvent event;
  while (reader->Read(&event)) {
    bool more = false;
    try {
      more = on_event(event);
    } catch (...) {
      context.TryCancel();
      reader->Finish();
      throw;
    }
    if (!more) {
      context.TryCancel();
      reader->Finish();
      return;
    }
  }
  check(reader->Finish());
  throw ClientError(grpc::StatusCode::UNAVAILABLE, "the server ended the watch");
}

}  // namespace tessera
