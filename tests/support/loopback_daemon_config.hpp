#pragma once
// The configuration the tests' in-process daemons start from.
#include <chrono>
#include <filesystem>

#include "server/config.hpp"

namespace tessera::test {

// A free loopback port, `threads` render threads, the job store in `data_dir`, warnings
// only, and no grace at shutdown: nothing in the tests needs running tiles to finish when
// they stop or restart a daemon.
inline server::DaemonConfig loopback_daemon_config(const std::filesystem::path& data_dir,
                                                   unsigned threads) {
  server::DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.threads = threads;
  config.data_dir = data_dir;
  config.log_level = "warn";
  config.shutdown_grace = std::chrono::milliseconds(0);
  return config;
}

}  // namespace tessera::test
