#pragma once
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/common.h>

#include "tessera/scene/scene_description.hpp"

namespace tessera::server {

inline constexpr const char* kDefaultListen = "127.0.0.1:50051";
inline constexpr const char* kDefaultDataDir = "./var";  // tesserad's default for --data
inline constexpr unsigned kMaxThreads = 1024;
// DaemonConfig::memory_budget's default: half the physical memory, read when the daemon starts.
inline constexpr std::size_t kMemoryBudgetAuto = static_cast<std::size_t>(-1);
inline constexpr std::size_t kMaxTileRetries = 100;

// The CPUs this process may use: min(hardware threads, affinity mask, ceil(cgroup CPU
// quota)), at least 1 (cpu_limits.hpp). Read once.
unsigned default_thread_count();

enum class LogFormat { kText, kJson };
std::optional<LogFormat> parse_log_format(const std::string& name);

// Everything a Daemon needs; tesserad fills it from flags and an optional YAML file.
struct DaemonConfig {
  std::string listen = kDefaultListen;        // HOST:PORT; port 0 picks a free one
  unsigned threads = default_thread_count();  // render worker threads
  // Render on every CUDA GPU found as well (key `gpus: all`, the default), or on the CPU
  // threads alone (`gpus: none`). Without the CUDA backend (no nvcc at build time) there
  // are none to use either way.
  bool gpus = true;
  // Pixels per GPU kernel launch: the scheduler hands a GPU consecutive tiles of a job up to
  // this many pixels at once (key `gpu_batch_pixels`). 0: the device's own size
  // (multiprocessors x 1024).
  std::size_t gpu_batch_pixels = 0;
  // Created at start if missing; holds the job store (jobs.sqlite3 and its WAL files).
  // Empty: the jobs live in memory only (in-process daemons in tests); tesserad defaults
  // to ./var.
  std::filesystem::path data_dir;
  // trace, debug, info, warn, error, critical, off. Process-wide, so tesserad's main()
  // applies it; an in-process Daemon leaves the host's logging alone.
  std::string log_level = "info";
  // text (spdlog's lines) or json (one object per line: log_format.hpp). Process-wide
  // like log_level.
  std::string log_format = "text";
  // HOST:PORT of the Prometheus /metrics endpoint (plain HTTP, its own port); empty: off.
  std::string metrics_listen;
  // Budgets. gRPC refuses a larger request before the daemon sees it (RESOURCE_EXHAUSTED);
  // 256 MiB carries inline meshes of ~20M triangles.
  std::size_t max_receive_message_bytes = std::size_t{256} << 20;
  // Width, height, pixels, samples per pixel, primitives: checked with the scene (config
  // keys max_width, max_height, max_pixels, max_samples_per_pixel, max_primitives).
  SceneLimits limits;
  // A job whose estimated memory (estimate_memory: description, geometry, BVH, images,
  // tiles in flight) exceeds this is refused at SubmitJob with RESOURCE_EXHAUSTED, before
  // its scene is converted. Checked per job, not against what running jobs hold now: those
  // finish, so a job that fits the budget is queued rather than refused for being early.
  // 0: no limit. Default: half the physical memory (default_memory_budget()).
  std::size_t memory_budget = kMemoryBudgetAuto;
  // A job whose scene preparation (BVH build and the rest) runs longer fails with an
  // error saying so; 0: no limit.
  std::chrono::milliseconds prepare_timeout{10 * 60 * 1000};
  // How long shutdown lets tiles in flight finish (and be stored) before abandoning them;
  // an abandoned tile stops within about a second and is rendered again after a restart.
  // Shutdown takes at most this plus about 2 s, so a container's stop grace period must be
  // longer.
  std::chrono::milliseconds shutdown_grace{5000};
  // Retention of finished jobs: deleted once finished longer than job_ttl ago (0: kept
  // however old), and the oldest finished deleted while more than max_jobs jobs are kept
  // (0: no limit). Unfinished jobs are never deleted.
  std::chrono::seconds job_ttl{7 * 24 * 3600};
  std::size_t max_jobs = 10000;
  // Queued and running jobs one submitter may have; more are refused with
  // RESOURCE_EXHAUSTED (0: no limit).
  std::size_t max_jobs_per_submitter = 1000;
  // How long one StreamTiles write may wait for a client that does not read before the
  // stream is ended (the client re-attaches with after_sequence), so a stalled reader never
  // holds a server thread for longer.
  std::chrono::milliseconds stream_write_timeout{30000};
  // Failed attempts at one tile (its render, encoding or storage threw) retried before the
  // job fails naming the tile: a tile gets tile_retries + 1 attempts in all (0 to 100).
  std::size_t tile_retries = 2;
  // WatchJobs: events buffered per watcher (beyond its opening snapshot), and how long one
  // write to a watcher may wait for its client to read; a watcher past either is dropped.
  std::size_t watch_buffer = 1024;
  std::chrono::milliseconds watch_write_timeout{10'000};
  // TLS (server_credentials.hpp): the server's certificate chain and private key, PEM files,
  // both or neither; empty: plaintext. With tls_client_ca (PEM, one or more CA certificates)
  // every client must present a certificate that CA signed (mTLS).
  std::filesystem::path tls_cert;
  std::filesystem::path tls_key;
  std::filesystem::path tls_client_ca;
  // Plaintext is served only on loopback (127.0.0.0/8, [::1], localhost): anyone on the
  // network could read the scenes and tiles, and the tokens. This lets a daemon listen
  // unencrypted on another address anyway (behind a TLS-terminating proxy, or in a
  // container whose port is published on loopback only).
  bool allow_insecure_remote = false;
  // YAML list of bearer tokens (access_tokens.hpp); empty: no authentication, every caller
  // may do everything.
  std::filesystem::path tokens_file;
};

// A bad setting; the message names the key (`threads: must be ...`), and the file when it
// came from one.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::optional<spdlog::level::level_enum> parse_log_level(const std::string& name);

// "500ms", "30s", "15m", "12h", "7d"; a plain number is seconds. Nothing when malformed,
// negative or beyond 100 years.
std::optional<std::chrono::milliseconds> parse_duration(const std::string& text);

// "512MiB", "8GiB", "1.5GB"... (KB/MB/GB/TB are powers of 1000, KiB/MiB/GiB/TiB of 1024);
// a plain number is bytes. Nothing when malformed or beyond 2^60.
std::optional<std::size_t> parse_size(const std::string& text);

// The memory budget in bytes (kMemoryBudgetAuto resolved; 0: no limit).
std::size_t effective_memory_budget(const DaemonConfig& config);

// Throws ConfigError for the first invalid setting.
void validate_config(const DaemonConfig& config);

// Reads the keys listen, threads, gpus, data, log_level, log_format, metrics_listen,
// shutdown_grace, job_ttl, max_jobs, max_jobs_per_submitter, tile_retries, watch_buffer,
// watch_write_timeout, stream_write_timeout, the security settings (tls_cert, tls_key,
// tls_client_ca, allow_insecure_remote, tokens) and the budgets (max_receive_message_bytes,
// max_width, max_height, max_pixels, max_samples_per_pixel, max_primitives, memory_budget,
// prepare_timeout) from a YAML file on top of `base`. Durations are a number with a unit:
// 500ms, 30s, 15m, 12h, 7d; sizes a number with an optional unit: 512MiB, 8GiB. Unknown keys
// are reported in `warnings`; bad values
// throw ConfigError naming file and key.
DaemonConfig load_config_file(const std::filesystem::path& path, DaemonConfig base,
                              std::vector<std::string>& warnings);
// The same from text; `display_name` appears in messages.
DaemonConfig load_config_yaml(const std::string& text, const std::string& display_name,
                              DaemonConfig base, std::vector<std::string>& warnings);

// Environment variables: every configuration key has one, TESSERAD_ and the key in capitals
// (listen: TESSERAD_LISTEN, max_pixels: TESSERAD_MAX_PIXELS), derived from the key so a new
// key gets its variable without a list to keep. Values are read as the file's are; an
// empty variable counts as unset.
inline constexpr const char* kEnvironmentPrefix = "TESSERAD_";
// Names the config file when --config is not given (it is not a key of the file).
inline constexpr const char* kConfigFileVariable = "TESSERAD_CONFIG";
using Environment = std::vector<std::pair<std::string, std::string>>;
std::string environment_variable_for(const std::string& key);
// Applies the TESSERAD_* variables of `environment` on top of `base`. Bad values throw
// ConfigError naming the variable; TESSERAD_* variables that name no key are reported in
// `warnings`.
DaemonConfig apply_environment(const Environment& environment, DaemonConfig base,
                               std::vector<std::string>& warnings);
// This process's environment.
Environment process_environment();

}  // namespace tessera::server
