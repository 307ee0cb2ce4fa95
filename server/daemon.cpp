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

#include <cstdio>
#include <random>
#include <thread>

#include "convert/scene_proto.hpp"
#include "server/access_control.hpp"
#include "server/job_registry.hpp"
#include "server/job_watch.hpp"
#include "server/listen_address.hpp"
#include "server/metrics.hpp"
#include "server/metrics_http.hpp"
#include "server/render_service.hpp"
#include "server/rpc_log.hpp"
#include "server/scheduler.hpp"
#include "server/server_credentials.hpp"
#include "server/server_info.hpp"
#if defined(TESSERA_HAS_CUDA)
#include "server/gpu_tile_device.hpp"
#endif
#include "server/sqlite_job_store.hpp"
#include "tessera/render/memory_estimate.hpp"

namespace tessera::server {

namespace {
constexpr const char* kServiceName = "tessera.v1.RenderService";
// After the tiles' grace period, calls still open (streams) get this long to end.
constexpr std::chrono::seconds kRpcShutdownGrace{1};
// Retention also runs on this period, so job_ttl applies to an idle daemon too.
constexpr std::chrono::seconds kRetentionPeriod{60};

// Reads a job's scene back from the store and converts it as at submission.
SceneDescription load_scene(JobStore& store, const Job& job, const SceneLimits& limits) {
  const auto source = store.scene(job.id());
  if (!source) throw std::runtime_error("the job's scene is missing from the store");
  v1::Scene scene;
  v1::RenderSettings settings;
  if (!scene.ParseFromString(source->scene_proto) ||
      !settings.ParseFromString(source->settings_proto))
    throw std::runtime_error("the job's stored scene is unreadable");
  SceneConversion conversion = scene_from_proto(scene, settings, limits);
  if (!conversion.ok())
    throw std::runtime_error("the stored scene no longer passes the checks: " +
                             describe_issues(conversion.issues));
  return std::move(*conversion.scene);
}

std::string random_owner() {
  std::random_device device;
  char text[32];
  std::snprintf(text, sizeof text, "tesserad-%08x", device());
  return text;
}

void log_security(const DaemonConfig& config, const ListenAddress& listen) {
  const std::string transport =
      config.tls_cert.empty()
          ? std::string("plaintext")
          : "TLS (" + config.tls_cert.string() +
                (config.tls_client_ca.empty()
                     ? std::string(")")
                     : ", client certificates from " + config.tls_client_ca.string() + ")");
  spdlog::info("security: {}, {}", transport,
               config.tokens_file.empty() ? std::string("no tokens: every caller may do everything")
                                          : "bearer tokens from " + config.tokens_file.string());
  if (config.tls_cert.empty() && !is_loopback_host(listen.host))
    spdlog::warn(
        "serving plaintext on {} (allow_insecure_remote): the network can read every scene, "
        "image and token",
        listen.host);
}

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

  std::unique_ptr<JobStore> store;
  std::unique_ptr<JobWatchHub> watch_hub;  // outlives the jobs, which report to it
  DaemonMetrics metrics;
  std::unique_ptr<MetricsJobListener> metrics_listener;  // before the hub, like the jobs
  std::unique_ptr<JobRegistry> jobs;
  std::unique_ptr<Scheduler> scheduler;
  std::unique_ptr<RenderServiceImpl> service;
  std::unique_ptr<grpc::Server> server;
  // Declared last, so destroyed first: its handler reads the store and the scheduler.
  std::unique_ptr<MetricsHttpServer> metrics_server;
  int metrics_port = 0;

  // Retention runs on its own thread, woken when a job finishes, so no RPC or worker
  // waits on deletions.
  std::thread retention_thread;
  std::mutex retention_mutex;
  std::condition_variable retention_cv;
  bool retention_due = true;
  bool retention_stop = false;

  void apply_retention() {
    RetentionPolicy policy;
    policy.ttl_ms = std::chrono::duration_cast<std::chrono::milliseconds>(config.job_ttl).count();
    policy.max_jobs = config.max_jobs;
    if (policy.ttl_ms == 0 && policy.max_jobs == 0) return;
    try {
      const auto deleted = store->apply_retention(policy, unix_millis_now());
      for (const std::string& id : deleted) {
        jobs->forget(id);
        JobRecord gone;  // retention knows only the id
        gone.id = id;
        watch_hub->job_deleted(gone);
      }
      if (!deleted.empty()) spdlog::info("retention deleted {} finished jobs", deleted.size());
    } catch (const std::exception& e) {
      spdlog::error("retention failed: {}", e.what());
    }
  }

  void retention_loop() {
    std::unique_lock lock(retention_mutex);
    while (!retention_stop) {
      if (retention_due) {
        retention_due = false;
        lock.unlock();
        apply_retention();
        lock.lock();
        continue;
      }
      retention_cv.wait_for(lock, kRetentionPeriod);
      retention_due = true;
    }
  }

  void request_retention() {
    {
      std::lock_guard lock(retention_mutex);
      retention_due = true;
    }
    retention_cv.notify_one();
  }

  // What a scrape of /metrics returns: the counters, and the gauges read now.
  std::string metrics_text() {
    MetricsSnapshot snapshot;
    try {
      snapshot.jobs_by_state = store->count_by_state();
    } catch (const std::exception& e) {
      spdlog::warn("metrics: cannot count the jobs: {}", e.what());
    }
    const SchedulerLoad load = scheduler->load();
    snapshot.queued_jobs = load.jobs_with_work;
    snapshot.pending_tiles = load.pending_tiles;
    snapshot.tiles_in_flight = load.in_flight;
    snapshot.render_threads = scheduler->threads();
    if (!config.data_dir.empty())
      for (const char* suffix : {"", "-wal", "-shm"}) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(
            config.data_dir / (std::string(SqliteJobStore::kFileName) + suffix), ec);
        if (!ec) snapshot.store_bytes += size;
      }
    snapshot.resident_bytes = resident_memory_bytes();
    return metrics.exposition(snapshot);
  }

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
  // Both read their files now, so a bad one stops the start before anything is opened.
  const auto credentials = make_server_credentials(d.config);
  AccessControl access = d.config.tokens_file.empty()
                             ? AccessControl()
                             : AccessControl(load_token_file(d.config.tokens_file));
  if (!d.config.data_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(d.config.data_dir, ec);
    if (ec || !std::filesystem::is_directory(d.config.data_dir))
      throw ConfigError("data: cannot create directory '" + d.config.data_dir.string() +
                        "': " + (ec ? ec.message() : "not a directory"));
  }

  d.store = std::make_unique<SqliteJobStore>(d.config.data_dir.empty()
                                                 ? std::filesystem::path(":memory:")
                                                 : d.config.data_dir / SqliteJobStore::kFileName);
  d.watch_hub = std::make_unique<JobWatchHub>(JobWatchHub::Options{
      .buffer_events = d.config.watch_buffer, .write_timeout = d.config.watch_write_timeout});
  d.metrics_listener = std::make_unique<MetricsJobListener>(d.metrics, d.watch_hub.get());
  d.jobs = std::make_unique<JobRegistry>(*d.store, d.metrics_listener.get());

  SchedulerOptions options;
  options.threads = d.config.threads;
  options.owner = random_owner();
  options.prepare_timeout = d.config.prepare_timeout;
  options.tile_retries = static_cast<std::uint32_t>(d.config.tile_retries);
  options.metrics = &d.metrics;
#if defined(TESSERA_HAS_CUDA)
  if (d.config.gpus) options.devices = gpu_tile_devices(d.config.gpu_batch_pixels);
#endif
  std::vector<std::string> gpu_names;
  for (const auto& device : options.devices) gpu_names.push_back(device->name());
  options.load_scene = [&d](const Job& job) { return load_scene(*d.store, job, d.config.limits); };
  options.on_job_released = [&d](const Job& job) {
    d.jobs->forget(job.id());
    d.request_retention();
  };
  d.scheduler = std::make_unique<Scheduler>(std::move(options));
  d.service = std::make_unique<RenderServiceImpl>(
      *d.jobs, *d.scheduler, d.config.limits, d.config.max_jobs_per_submitter,
      std::chrono::milliseconds(100), d.config.stream_write_timeout);
  d.service->set_memory_budget(effective_memory_budget(d.config));
  d.service->enable_watch(*d.watch_hub);
  d.service->set_server_info(make_server_info(d.config, gpu_names));
  d.service->set_access_control(std::move(access));

  // Jobs a previous run left queued or running carry on where they stopped; paused ones
  // stay paused (live, so ResumeJob finds them) until resumed.
  const std::vector<JobRecord> unfinished = d.store->unfinished_jobs();
  for (const JobRecord& record : unfinished) {
    auto job = d.jobs->adopt(record);
    if (is_runnable(record.state)) d.scheduler->submit(std::move(job));
  }
  if (!unfinished.empty())
    spdlog::info("resuming {} unfinished jobs from {}", unfinished.size(),
                 d.config.data_dir.string());

  if (!d.config.metrics_listen.empty()) {
    d.metrics_server = std::make_unique<MetricsHttpServer>([&d] { return d.metrics_text(); });
    try {
      d.metrics_port = d.metrics_server->start(d.config.metrics_listen);
    } catch (...) {
      d.metrics_server.reset();
      d.scheduler->stop();
      throw;
    }
  }

  // Both register process-wide hooks that ServerBuilder consults; calling them again is
  // harmless.
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int bound_port = 0;
  builder.AddListeningPort(d.config.listen, credentials, &bound_port);
  // Without this, Linux lets a second daemon bind the same port and share its traffic.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.RegisterService(d.service.get());
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(make_rpc_log_interceptor());
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  builder.SetMaxReceiveMessageSize(static_cast<int>(
      std::min<std::size_t>(d.config.max_receive_message_bytes, std::numeric_limits<int>::max())));
  d.server = builder.BuildAndStart();
  if (!d.server || bound_port == 0) {
    d.server.reset();
    d.metrics_server.reset();
    d.scheduler->stop();
    throw std::runtime_error("listen: cannot listen on " + d.config.listen +
                             " (address in use, or not an address of this machine?)");
  }
  d.scheduler->start();
  d.retention_thread = std::thread([&d] { d.retention_loop(); });
  if (auto* health = d.server->GetHealthCheckService())
    health->SetServingStatus(kServiceName, true);
  d.set_state(Impl::State::kRunning, bound_port, connectable_host(listen.host));
  spdlog::info("tesserad {} listening on {} with {} render threads", TESSERA_VERSION,
               listen.host + ":" + std::to_string(bound_port), d.config.threads);
  if (d.metrics_server)
    spdlog::info("metrics at http://{}:{}/metrics",
                 std::get<ListenAddress>(parse_listen_address(d.config.metrics_listen)).host,
                 d.metrics_port);
  log_security(d.config, listen);
  const std::size_t budget = effective_memory_budget(d.config);
  spdlog::info("budgets: memory {} per job, messages up to {}, preparation {}",
               budget == 0 ? std::string("unlimited") : format_bytes(budget),
               format_bytes(d.config.max_receive_message_bytes),
               d.config.prepare_timeout.count() == 0
                   ? std::string("unlimited")
                   : std::to_string(d.config.prepare_timeout.count() / 1000) + " s");
  return bound_port;
}

void Daemon::shutdown() {
  Impl& d = *impl_;
  std::lock_guard lifecycle(d.lifecycle_mutex);
  if (d.state != Impl::State::kRunning) return;
  spdlog::info("tesserad shutting down");
  if (auto* health = d.server->GetHealthCheckService()) health->Shutdown();
  d.service->stop_accepting();
  // Tiles in flight get the grace period to finish and be stored; the jobs themselves stay
  // queued or running in the store, for the next start to resume.
  d.scheduler->stop(d.config.shutdown_grace);
  // Streams of unfinished jobs notice stop_accepting() within their poll interval and end
  // with UNAVAILABLE; streams of finished jobs may take longer and are cut off below.
  d.service->wait_for_streams(kRpcShutdownGrace);
  d.server->Shutdown(std::chrono::system_clock::now() + kRpcShutdownGrace);
  d.server->Wait();
  d.server.reset();
  if (d.metrics_server) d.metrics_server->stop();
  {
    std::lock_guard lock(d.retention_mutex);
    d.retention_stop = true;
  }
  d.retention_cv.notify_all();
  if (d.retention_thread.joinable()) d.retention_thread.join();
  d.set_state(Impl::State::kStopped, d.port, d.host);
  spdlog::info("tesserad stopped");
}

void Daemon::wait() {
  Impl& d = *impl_;
  std::unique_lock lock(d.state_mutex);
  d.stopped_cv.wait(lock, [&] { return d.state != Impl::State::kRunning; });
}

int Daemon::metrics_port() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->metrics_port;
}

std::string Daemon::metrics_text() {
  std::lock_guard lifecycle(impl_->lifecycle_mutex);
  if (impl_->state != Impl::State::kRunning) return {};
  return impl_->metrics_text();
}

int Daemon::port() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->port;
}

std::string Daemon::address() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->host + ":" + std::to_string(impl_->port);
}

std::size_t Daemon::watcher_count() const {
  return impl_->watch_hub ? impl_->watch_hub->watcher_count() : 0;
}

const DaemonConfig& Daemon::config() const {
  return impl_->config;
}

int Daemon::open_streams() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->service ? impl_->service->open_streams() : 0;
}

std::uint64_t Daemon::stream_write_timeouts() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->service ? impl_->service->stream_write_timeouts() : 0;
}

}  // namespace tessera::server
