#pragma once
#include <memory>
#include <string>

#include "server/config.hpp"

namespace tessera::server {

// The whole render daemon in one object: job store (SQLite in the data directory, or in
// memory without one), scheduler with its worker threads and the gRPC server
// (RenderService, the standard health service and reflection).
// tesserad's main() is a Daemon plus signal handling; tests run one in-process on port 0.
class Daemon {
 public:
  explicit Daemon(DaemonConfig config);
  ~Daemon();  // shutdown()
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  // Validates the config, creates the data directory, opens the job store and queues the
  // jobs it holds unfinished, starts the workers and binds the listening address. Returns the bound
  // port (the one chosen when the config says 0). Throws ConfigError for a bad config and
  // std::runtime_error when it cannot listen. Call once.
  int start();

  // Stops accepting jobs, lets tiles in flight finish for up to config().shutdown_grace
  // (then abandons the rest, which stop within about a second), ends the streams of
  // unfinished jobs with UNAVAILABLE and joins every thread. Jobs are not cancelled: they
  // stay queued or running in the store and resume at the next start. Idempotent and safe
  // from any thread except a gRPC handler's.
  void shutdown();

  // Blocks until shutdown() has finished; returns at once if the daemon never started.
  void wait();

  int port() const;  // 0 before start()
  // The /metrics port (config().metrics_listen; 0 when off or before start()), and the
  // text a scrape returns now (empty unless running), for tests.
  int metrics_port() const;
  std::string metrics_text();
  std::string address() const;  // "HOST:PORT" with the bound port, for clients
  const DaemonConfig& config() const;
  // StreamTiles calls open now, and those ended by the stream write timeout (0 before
  // start()).
  int open_streams() const;
  std::uint64_t stream_write_timeouts() const;
  // WatchJobs streams open now (dropped watchers are gone from it once their call ended).
  std::size_t watcher_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tessera::server
