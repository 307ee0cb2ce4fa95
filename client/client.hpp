#pragma once
#include <grpcpp/channel.h>

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "client/client_error.hpp"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera {

// How a client proves who it is and whom it talks to. Over plaintext (the default) the
// server must be on loopback or allow insecure remotes.
struct ClientTls {
  bool enabled = false;
  // The CA certificates (PEM) the server's certificate must chain to; empty: gRPC's default
  // roots (the system's, or GRPC_DEFAULT_SSL_ROOTS_FILE_PATH).
  std::string root_certs_pem;
  // For mutual TLS: this client's certificate chain and private key (PEM), both or neither.
  std::string client_cert_pem;
  std::string client_key_pem;
};

struct ClientOptions {
  // A gRPC target: "host:port", "dns:///host:port", "unix:/path".
  std::string target = "127.0.0.1:50051";
  // Get, list, cancel and delete are quick on the server; a stuck call means a stuck server.
  std::chrono::milliseconds unary_deadline{10'000};
  // Submit carries the whole scene, meshes inline, so it may take a while to send.
  std::chrono::milliseconds submit_deadline{120'000};
  // Attempts of a submit whose request has a request_id, when an attempt ends with
  // DEADLINE_EXCEEDED or UNAVAILABLE (the request id makes a retry safe: the daemon returns
  // the job an earlier attempt created). Waits submit_retry_pause, doubling, in between.
  int submit_attempts = 4;
  std::chrono::milliseconds submit_retry_pause{500};
  // How long stream_tiles keeps re-attaching to a daemon that went away (restarting)
  // since the last tile it received; 0: not at all.
  std::chrono::milliseconds reconnect_window{60'000};
  // Sent as `authorization: Bearer <token>` with every call of the channel make_channel
  // builds (tesserad --tokens); empty: none.
  std::string token{};
  ClientTls tls{};
};

// A connection to one tesserad. Thread-safe: calls may run concurrently (a stream on one
// thread, a cancel on another). Every failed call throws ClientError with the gRPC code and
// message.
class Client {
 public:
  // Over make_channel(options): TLS and the token as the options say.
  explicit Client(ClientOptions options = {});
  // Over an existing channel (in-process servers in tests); the channel carries the
  // credentials, so options.tls and options.token are not used.
  Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options = {});
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Submits a job. With request.request_id() set, retries on DEADLINE_EXCEEDED and
  // UNAVAILABLE (options.submit_attempts in all) with the same id, so a timeout never leaves
  // the caller with two jobs; without one, a single attempt.
  v1::Job submit(const v1::SubmitJobRequest& request);

  using TileCallback = std::function<void(const v1::Tile&)>;
  // Calls `on_tile` for every delivery of the job (every tile, or with passes every pass of
  // every tile), on the calling thread, until the stream ends. When the daemon goes away (a
  // restart), re-attaches after the last delivery received (after_sequence), for
  // up to options.reconnect_window, so every tile still arrives exactly once. Returns when
  // the job completed; throws ClientError with CANCELLED when the job was
  // cancelled, ABORTED (and the reason) when it failed, or the transport's error. If
  // `on_tile` throws, the stream is cancelled and the exception propagates.
  void stream_tiles(const std::string& job_id, const TileCallback& on_tile);

  // Ends a stream_tiles running on another thread (Ctrl-C): it throws ClientError with
  // CANCELLED, and later calls of stream_tiles do at once. Thread-safe.
  void stop_streams();

  v1::Job get(const std::string& job_id);
  // Every job matching the request's filters (state, submitter, label, name), newest
  // first, page after page; the request's page fields are ignored.
  std::vector<v1::Job> list(v1::ListJobsRequest filters = {});
  v1::ListJobsResponse list_page(const v1::ListJobsRequest& request);
  // Deletes a finished job (DeleteJob).
  void remove(const std::string& job_id);
  v1::Job cancel(const std::string& job_id);
  v1::Job pause(const std::string& job_id);
  v1::Job resume(const std::string& job_id);
  v1::Job retry(const std::string& job_id);
  v1::Job update(const v1::UpdateJobRequest& request);

  // Return false to stop watching.
  using JobEventCallback = std::function<bool(const v1::JobEvent&)>;
  // Calls `on_event` for each event of WatchJobs (the snapshot first), on the calling
  // thread, until it returns false (then returns normally) or the stream ends (then throws
  // ClientError with the server's status: a watch never ends on its own with OK).
  void watch_jobs(const v1::WatchJobsRequest& request, const JobEventCallback& on_event);

  // GetServerInfo: the daemon's version, build, devices, limits and capabilities.
  v1::ServerInfo server_info();
  // The grpc.health.v1 check of the daemon's RenderService: true when SERVING. Throws
  // ClientError when the daemon cannot be reached or answers with an error.
  bool healthy();

  const std::string& target() const { return options_.target; }

 private:
  ClientOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::RenderService::Stub> stub_;
  std::mutex streams_mutex_;
  grpc::ClientContext* open_stream_ = nullptr;  // the stream stop_streams() cancels
  bool streams_stopped_ = false;
};

// Trailing metadata key of a StreamTiles that ended UNAVAILABLE because the daemon is
// stopping with the job kept: the stream can be re-attached once it is back.
inline constexpr const char* kJobResumesMetadataKey = "tessera-job-resumes";

// A fresh random request id for SubmitJobRequest.request_id: 32 hex digits (128 bits from
// std::random_device), so two clients never pick the same one.
std::string make_request_id();

// A plaintext channel to `target` with message limits large enough for big tiles.
std::shared_ptr<grpc::Channel> make_channel(const std::string& target);
// The same to options.target, over TLS when options.tls.enabled, adding options.token to
// every call's metadata (an interceptor, so every stub on the channel sends it, over
// plaintext too: gRPC's call credentials would refuse a plaintext channel).
std::shared_ptr<grpc::Channel> make_channel(const ClientOptions& options);

}  // namespace tessera
