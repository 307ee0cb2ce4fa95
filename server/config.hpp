#pragma once
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/common.h>

#include "tessera/scene/scene_description.hpp"

namespace tessera::server {

inline constexpr const char* kDefaultListen = "127.0.0.1:50051";
inline constexpr const char* kDefaultDataDir = "./var";  // tesserad's default for --data
inline constexpr unsigned kMaxThreads = 1024;

// std::thread::hardware_concurrency(), or 1 where it is unknown.
unsigned default_thread_count();

// Everything a Daemon needs; tesserad fills it from flags and an optional YAML file.
struct DaemonConfig {
  std::string listen = kDefaultListen;        // HOST:PORT; port 0 picks a free one
  unsigned threads = default_thread_count();  // render worker threads
  // Created at start if missing. Empty: none (in-process daemons in tests); tesserad
  // defaults to ./var. Holds nothing yet; job persistence will live here.
  std::filesystem::path data_dir;
  // trace, debug, info, warn, error, critical, off. Process-wide, so tesserad's main()
  // applies it; an in-process Daemon leaves the host's logging alone.
  std::string log_level = "info";
  std::size_t max_receive_message_bytes = std::size_t{256} << 20;  // large inline meshes
  SceneLimits limits;
  // How long shutdown waits for RPCs in progress before cancelling them.
  std::chrono::milliseconds shutdown_grace{5000};
};

// A bad setting; the message names the key (`threads: must be ...`), and the file when it
// came from one.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::optional<spdlog::level::level_enum> parse_log_level(const std::string& name);

// Throws ConfigError for the first invalid setting.
void validate_config(const DaemonConfig& config);

// Reads the keys listen, threads, data and log_level from a YAML file on top of `base`.
// Unknown keys are reported in `warnings`; bad values throw ConfigError naming file and key.
DaemonConfig load_config_file(const std::filesystem::path& path, DaemonConfig base,
                              std::vector<std::string>& warnings);
// The same from text; `display_name` appears in messages.
DaemonConfig load_config_yaml(const std::string& text, const std::string& display_name,
                              DaemonConfig base, std::vector<std::string>& warnings);

}  // namespace tessera::server
