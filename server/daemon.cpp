#include "server/daemon.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <system_error>
#include <variant>

#include "server/job_store.hpp"
#include "server/listen_address.hpp"
#include "server/render_service.hpp"
#include "server/scheduler.hpp"

namespace tessera::server {

namespace {
constexpr const char* kServiceName = "tessera.v1.RenderService";
constexpr const char* kShutdownReason = "daemon shutting down";

// A client cannot dial the wildcard address the server listens on; loopback reaches it.
std::string connectable_host(const std::string& host) {
  if (host == "0.0.0.0") return "127.0.0.1";
  if (host == "[::]") return "[::1]";
  return host;
}
}  // namespace

struct Daemon::Impl {
  explicit Impl(DaemonConfig c) : config(std::move(c)) {}

  DaemonConfig config;
  std::mutex lifecycle_mutex;  // serialises start() and shutdown()
  std::mutex state_mutex;      // guards `state` for wait()
  std::condition_variable stopped_cv;
  enum class State { kNew, kRunning, kStopped } state = State::kNew;
  int port = 0;
  std::string host;

  InMemoryJobStore store;
  std::unique_ptr<Scheduler> scheduler;
  std::unique_ptr<RenderServiceImpl> service;
  std::unique_ptr<grpc::Server> server;

  void set_state(State s, int bound_port, std::string bound_host) {
    {
      std::lock_guard lock(state_mutex);
      state = s;
      port = bound_port;
      host = std::move(bound_host);
    }
    stopped_cv.notify_all();
  }
};

Daemon::Daemon(DaemonConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}

Daemon::~Daemon() {
  shutdown();
}

int Daemon::start() {
  Impl& d = *impl_;
  std::lock_guard lifecycle(d.lifecycle_mutex);
  if (d.state != Impl::State::kNew) throw std::logic_error("Daemon::start() may be called once");

  validate_config(d.config);
  const ListenAddress listen = std::get<ListenAddress>(parse_listen_address(d.config.listen));
  if (!d.config.data_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(d.config.data_dir, ec);
    if (ec || !std::filesystem::is_directory(d.config.data_dir))
      throw ConfigError("data: cannot create directory '" + d.config.data_dir.string() +
                        "': " + (ec ? ec.message() : "not a directory"));
  }

  SchedulerOptions options;
  options.threads = d.config.threads;
  d.scheduler = std::make_unique<Scheduler>(std::move(options));
  d.service = std::make_unique<RenderServiceImpl>(d.store, *d.scheduler, d.config.limits);

  // Both register process-wide hooks that ServerBuilder consults; calling them again is
  // harmless.
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int bound_port = 0;
  builder.AddListeningPort(d.config.listen, grpc::InsecureServerCredentials(), &bound_port);
  // Without this, Linux lets a second daemon bind the same port and share its traffic.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.RegisterService(d.service.get());
  builder.SetMaxReceiveMessageSize(static_cast<int>(
      std::min<std::size_t>(d.config.max_receive_message_bytes, std::numeric_limits<int>::max())));
  d.server = builder.BuildAndStart();
  if (!d.server || bound_port == 0) {
    d.server.reset();
    d.scheduler->stop(kShutdownReason);
    throw std::runtime_error("listen: cannot listen on " + d.config.listen +
                             " (address in use, or not an address of this machine?)");
  }
  d.scheduler->start();
  if (auto* health = d.server->GetHealthCheckService())
    health->SetServingStatus(kServiceName, true);
  d.set_state(Impl::State::kRunning, bound_port, connectable_host(listen.host));
  spdlog::info("tesserad {} listening on {} with {} render threads", TESSERA_VERSION,
               listen.host + ":" + std::to_string(bound_port), d.config.threads);
  return bound_port;
}

void Daemon::shutdown() {
  Impl& d = *impl_;
  std::lock_guard lifecycle(d.lifecycle_mutex);
  if (d.state != Impl::State::kRunning) return;
  spdlog::info("tesserad shutting down");
  if (auto* health = d.server->GetHealthCheckService()) health->Shutdown();
  d.service->stop_accepting();
  // Cancelling the jobs first ends every StreamTiles call, so the server's shutdown below
  // rarely needs its grace period.
  d.scheduler->stop(kShutdownReason);
  d.server->Shutdown(std::chrono::system_clock::now() + d.config.shutdown_grace);
  d.server->Wait();
  d.server.reset();
  d.set_state(Impl::State::kStopped, d.port, d.host);
  spdlog::info("tesserad stopped");
}

void Daemon::wait() {
  Impl& d = *impl_;
  std::unique_lock lock(d.state_mutex);
  d.stopped_cv.wait(lock, [&] { return d.state != Impl::State::kRunning; });
}

int Daemon::port() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->port;
}

std::string Daemon::address() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->host + ":" + std::to_string(impl_->port);
}

const DaemonConfig& Daemon::config() const {
  return impl_->config;
}

}  // namespace tessera::server
