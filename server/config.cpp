#include "server/config.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>
#include <sstream>
#include <variant>

#include "server/cpu_limits.hpp"
#include "server/job_cost.hpp"
#include "server/listen_address.hpp"
#include "server/yaml_document.hpp"

namespace tessera::server {
namespace {

constexpr const char* kLogLevels = "trace, debug, info, warn, error, critical or off";
// The display name under which settings from the environment are applied.
constexpr const char* kEnvironmentSource = "<environment>";

bool apply_setting(DaemonConfig& config, const std::string& display_name, const std::string& key,
                   const YAML::Node& value);

std::string located(const std::string& file, const YAML::Node& node, const std::string& key) {
  // A setting from the environment is named by its variable, whatever the key.
  if (file == kEnvironmentSource) return environment_variable_for(key);
  // Appended piecewise: `":" + std::to_string(...)` trips a false -Wrestrict in GCC 12.
  std::string where = file;
  if (!node.Mark().is_null()) where.append(":").append(std::to_string(node.Mark().line + 1));
  return where.append(": ").append(key);
}

std::string scalar_text(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "nothing";
}

std::string read_string(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar())
    throw ConfigError(located(file, node, key) + ": must be a string, got " + scalar_text(node));
  return node.Scalar();
}

std::chrono::milliseconds read_duration(const std::string& file, const YAML::Node& node,
                                        const std::string& key) {
  const auto duration = node.IsScalar() ? parse_duration(node.Scalar()) : std::nullopt;
  if (!duration)
    throw ConfigError(located(file, node, key) +
                      ": must be a duration such as 30s, 15m, 12h or 7d, got " + scalar_text(node));
  return *duration;
}

std::size_t read_count(const std::string& file, const YAML::Node& node, const std::string& key) {
  long long count = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, count) || count < 0)
    throw ConfigError(located(file, node, key) + ": must be a whole number, 0 for no limit, got " +
                      scalar_text(node));
  return static_cast<std::size_t>(count);
}

std::size_t read_size(const std::string& file, const YAML::Node& node, const std::string& key) {
  const auto size = node.IsScalar() ? parse_size(node.Scalar()) : std::nullopt;
  if (!size)
    throw ConfigError(located(file, node, key) +
                      ": must be a size such as 512MiB or 8GiB (a plain number is bytes), got " +
                      scalar_text(node));
  return *size;
}

// A limit that must be at least 1: a whole number from 1 to `largest`.
std::uint64_t read_limit(const std::string& file, const YAML::Node& node, const std::string& key,
                         std::uint64_t largest) {
  long long value = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, value) || value < 1 ||
      static_cast<unsigned long long>(value) > largest)
    throw ConfigError(located(file, node, key) + ": must be a whole number from 1 to " +
                      std::to_string(largest) + ", got " + scalar_text(node));
  return static_cast<std::uint64_t>(value);
}

// The renderer's own bounds, which a configuration may lower but not raise.
constexpr std::uint32_t kLargestDimension = 65536;
constexpr std::uint32_t kLargestSamplesPerPixel = 65536;  // Sobol sample indices: 16 bits
// A launch's films live in device memory: 64 Mi pixels are 1 GiB of RGBA, 7 GiB with every AOV.
constexpr long long kLargestGpuBatchPixels = 1ll << 26;
constexpr std::size_t kLargestPrimitives = (std::size_t{1} << 27) - 1;  // reference index bits

constexpr const char* kKeys =
    "listen, threads, gpus, gpu_batch_pixels, data, log_level, log_format, metrics_listen, "
    "shutdown_grace, job_ttl, "
    "max_jobs, max_jobs_per_submitter, max_receive_message_bytes, max_width, max_height, "
    "max_pixels, "
    "max_samples_per_pixel, max_primitives, memory_budget, prepare_timeout, stream_write_timeout, "
    "tile_retries, watch_buffer, watch_write_timeout, tls_cert, tls_key, tls_client_ca, "
    "allow_insecure_remote, tokens";

bool read_bool(const std::string& file, const YAML::Node& node, const std::string& key) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
    throw ConfigError(located(file, node, key) + ": must be true or false, got " +
                      scalar_text(node));
  return value;
}

std::filesystem::path read_path(const std::string& file, const YAML::Node& node,
                                const std::string& key) {
  const std::string path = read_string(file, node, key);
  if (path.empty()) throw ConfigError(located(file, node, key) + ": must not be empty");
  return path;
}

// The pairing of the TLS settings, and plaintext only where the network cannot listen in.
// The files themselves are read when the daemon starts (server_credentials.hpp).
void validate_transport_security(const DaemonConfig& config, const ListenAddress& listen) {
  if (config.tls_cert.empty() != config.tls_key.empty())
    throw ConfigError(config.tls_cert.empty()
                          ? "tls_cert: is required with tls_key (the certificate of that key)"
                          : "tls_key: is required with tls_cert (the certificate's private key)");
  if (!config.tls_client_ca.empty() && config.tls_cert.empty())
    throw ConfigError(
        "tls_client_ca: needs tls_cert and tls_key; client certificates are checked only over "
        "TLS");
  if (config.tls_cert.empty() && !config.allow_insecure_remote && !is_loopback_host(listen.host))
    throw ConfigError(
        "listen: " + config.listen +
        " can be reached from other machines, and without TLS they would see every scene, "
        "image and token in plaintext; set tls_cert and tls_key (--tls-cert, --tls-key), "
        "listen on loopback (127.0.0.1), or set allow_insecure_remote: true "
        "(--allow-insecure-remote) to serve plaintext anyway, e.g. behind a TLS proxy");
}

}  // namespace

std::optional<std::size_t> parse_size(const std::string& text) {
  std::size_t digits = 0;
  bool point = false;
  while (digits < text.size() &&
         ((text[digits] >= '0' && text[digits] <= '9') || (text[digits] == '.' && !point))) {
    point = point || text[digits] == '.';
    ++digits;
  }
  if (digits == 0 || digits > 20 || text[0] == '.') return std::nullopt;
  double value = 0.0;
  try {
    value = std::stod(text.substr(0, digits));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  std::string unit = text.substr(digits);
  while (!unit.empty() && unit.front() == ' ') unit.erase(unit.begin());
  double scale = 0.0;
  if (unit.empty() || unit == "B")
    scale = 1.0;
  else if (unit == "KiB")
    scale = 1024.0;
  else if (unit == "MiB")
    scale = 1024.0 * 1024.0;
  else if (unit == "GiB")
    scale = 1024.0 * 1024.0 * 1024.0;
  else if (unit == "TiB")
    scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else if (unit == "KB" || unit == "kB")
    scale = 1e3;
  else if (unit == "MB")
    scale = 1e6;
  else if (unit == "GB")
    scale = 1e9;
  else if (unit == "TB")
    scale = 1e12;
  else
    return std::nullopt;
  const double bytes = value * scale;
  if (!(bytes <= static_cast<double>(std::size_t{1} << 60))) return std::nullopt;
  return static_cast<std::size_t>(bytes);
}

std::size_t effective_memory_budget(const DaemonConfig& config) {
  return config.memory_budget == kMemoryBudgetAuto ? default_memory_budget() : config.memory_budget;
}

std::optional<std::chrono::milliseconds> parse_duration(const std::string& text) {
  std::size_t digits = 0;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
  if (digits == 0 || digits > 12) return std::nullopt;
  const long long value = std::stoll(text.substr(0, digits));
  const std::string unit = text.substr(digits);
  long long unit_ms = 0;
  if (unit.empty() || unit == "s")
    unit_ms = 1000;
  else if (unit == "ms")
    unit_ms = 1;
  else if (unit == "m")
    unit_ms = 60'000;
  else if (unit == "h")
    unit_ms = 3'600'000;
  else if (unit == "d")
    unit_ms = 86'400'000;
  else
    return std::nullopt;
  constexpr long long kHundredYearsMs = 100LL * 365 * 86'400'000;
  if (value > kHundredYearsMs / unit_ms) return std::nullopt;
  return std::chrono::milliseconds(value * unit_ms);
}

unsigned default_thread_count() {
  static const unsigned threads = thread_count_for(current_cpu_limits());
  return threads;
}

std::optional<LogFormat> parse_log_format(const std::string& name) {
  if (name == "text") return LogFormat::kText;
  if (name == "json") return LogFormat::kJson;
  return std::nullopt;
}

std::string environment_variable_for(const std::string& key) {
  std::string name = kEnvironmentPrefix;
  for (const char c : key) name += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return name;
}

DaemonConfig apply_environment(const Environment& environment, DaemonConfig config,
                               std::vector<std::string>& warnings) {
  const std::string prefix = kEnvironmentPrefix;
  for (const auto& [name, value] : environment) {
    if (name.rfind(prefix, 0) != 0 || value.empty()) continue;
    if (name == kConfigFileVariable) continue;  // names the file, read before this
    std::string key = name.substr(prefix.size());
    for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    // The variable's exact spelling: TESSERAD_threads is not TESSERAD_THREADS.
    if (environment_variable_for(key) != name || key.empty() ||
        !apply_setting(config, kEnvironmentSource, key, YAML::Node(value)))
      warnings.push_back(name + ": not a tesserad setting, ignored");
  }
  return config;
}

Environment process_environment() {
  Environment environment;
  for (char** entry = environ; entry && *entry; ++entry) {
    const std::string_view text(*entry);
    const auto equals = text.find('=');
    if (equals == std::string_view::npos) continue;
    environment.emplace_back(std::string(text.substr(0, equals)),
                             std::string(text.substr(equals + 1)));
  }
  return environment;
}

std::optional<spdlog::level::level_enum> parse_log_level(const std::string& name) {
  using namespace spdlog::level;
  if (name == "trace") return trace;
  if (name == "debug") return debug;
  if (name == "info") return info;
  if (name == "warn" || name == "warning") return warn;
  if (name == "error") return err;
  if (name == "critical") return critical;
  if (name == "off") return off;
  return std::nullopt;
}

void validate_config(const DaemonConfig& config) {
  const auto listen = parse_listen_address(config.listen);
  if (const auto* problem = std::get_if<std::string>(&listen))
    throw ConfigError("listen: " + *problem);
  if (config.threads < 1 || config.threads > kMaxThreads)
    throw ConfigError("threads: must be from 1 to " + std::to_string(kMaxThreads) + ", got " +
                      std::to_string(config.threads));
  if (!parse_log_level(config.log_level))
    throw ConfigError("log_level: must be one of " + std::string(kLogLevels) + ", got '" +
                      config.log_level + "'");
  if (config.max_receive_message_bytes < (std::size_t{1} << 20) ||
      config.max_receive_message_bytes > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw ConfigError("max_receive_message_bytes: must be from 1 MiB to 2 GiB - 1 (gRPC's limit)");
  const SceneLimits& limits = config.limits;
  if (limits.max_width < 1 || limits.max_width > kLargestDimension)
    throw ConfigError("max_width: must be from 1 to " + std::to_string(kLargestDimension));
  if (limits.max_height < 1 || limits.max_height > kLargestDimension)
    throw ConfigError("max_height: must be from 1 to " + std::to_string(kLargestDimension));
  if (limits.max_pixels < 1) throw ConfigError("max_pixels: must be at least 1");
  if (limits.max_samples_per_pixel < 1 || limits.max_samples_per_pixel > kLargestSamplesPerPixel)
    throw ConfigError("max_samples_per_pixel: must be from 1 to " +
                      std::to_string(kLargestSamplesPerPixel));
  if (limits.max_primitives < 1 || limits.max_primitives > kLargestPrimitives)
    throw ConfigError("max_primitives: must be from 1 to " + std::to_string(kLargestPrimitives));
  if (config.stream_write_timeout < std::chrono::milliseconds(1))
    throw ConfigError("stream_write_timeout: must be at least 1ms, got " +
                      std::to_string(config.stream_write_timeout.count()) + "ms");
  if (config.tile_retries > kMaxTileRetries)
    throw ConfigError("tile_retries: must be from 0 to " + std::to_string(kMaxTileRetries) +
                      ", got " + std::to_string(config.tile_retries));
  if (config.watch_buffer < 1) throw ConfigError("watch_buffer: must be at least 1 event");
  if (config.watch_write_timeout <= std::chrono::milliseconds(0))
    throw ConfigError("watch_write_timeout: must be longer than 0");
  if (!config.metrics_listen.empty()) {
    const auto metrics = parse_listen_address(config.metrics_listen);
    if (const auto* problem = std::get_if<std::string>(&metrics))
      throw ConfigError("metrics_listen: " + *problem);
  }
  if (!parse_log_format(config.log_format))
    throw ConfigError("log_format: must be text or json, got '" + config.log_format + "'");
  validate_transport_security(config, std::get<ListenAddress>(listen));
}

namespace {

// One setting, from a file or (display_name kEnvironmentSource) an environment variable:
// the one list of keys, so every key has its variable. False for an unknown key.
bool apply_setting(DaemonConfig& config, const std::string& display_name, const std::string& key,
                   const YAML::Node& value) {
  {
    if (key == "listen") {
      config.listen = read_string(display_name, value, key);
      const auto listen = parse_listen_address(config.listen);
      if (const auto* problem = std::get_if<std::string>(&listen))
        throw ConfigError(located(display_name, value, key) + ": " + *problem);
    } else if (key == "threads") {
      long long threads = 0;
      if (!value.IsScalar() || !YAML::convert<long long>::decode(value, threads) || threads < 1 ||
          threads > kMaxThreads)
        throw ConfigError(located(display_name, value, key) + ": must be an integer from 1 to " +
                          std::to_string(kMaxThreads) + ", got " + scalar_text(value));
      config.threads = static_cast<unsigned>(threads);
    } else if (key == "gpus") {
      const std::string gpus = read_string(display_name, value, key);
      if (gpus != "all" && gpus != "none")
        throw ConfigError(located(display_name, value, key) + ": must be all or none, got '" +
                          gpus + "'");
      config.gpus = gpus == "all";
    } else if (key == "gpu_batch_pixels") {
      long long pixels = 0;
      if (!value.IsScalar() || !YAML::convert<long long>::decode(value, pixels) || pixels < 0 ||
          pixels > kLargestGpuBatchPixels)
        throw ConfigError(located(display_name, value, key) +
                          ": must be a whole number from 0 (the device's own size) to " +
                          std::to_string(kLargestGpuBatchPixels) + ", got " + scalar_text(value));
      config.gpu_batch_pixels = static_cast<std::size_t>(pixels);
    } else if (key == "data") {
      const std::string data = read_string(display_name, value, key);
      if (data.empty())
        throw ConfigError(located(display_name, value, key) + ": must not be empty");
      config.data_dir = data;
    } else if (key == "log_level") {
      config.log_level = read_string(display_name, value, key);
      if (!parse_log_level(config.log_level))
        throw ConfigError(located(display_name, value, key) + ": must be one of " + kLogLevels +
                          ", got '" + config.log_level + "'");
    } else if (key == "shutdown_grace") {
      config.shutdown_grace = read_duration(display_name, value, key);
    } else if (key == "job_ttl") {
      config.job_ttl =
          std::chrono::duration_cast<std::chrono::seconds>(read_duration(display_name, value, key));
    } else if (key == "max_jobs") {
      config.max_jobs = read_count(display_name, value, key);
    } else if (key == "max_jobs_per_submitter") {
      config.max_jobs_per_submitter = read_count(display_name, value, key);
    } else if (key == "stream_write_timeout") {
      config.stream_write_timeout = read_duration(display_name, value, key);
      if (config.stream_write_timeout < std::chrono::milliseconds(1))
        throw ConfigError(located(display_name, value, key) + ": must be at least 1ms, got " +
                          scalar_text(value));
    } else if (key == "max_receive_message_bytes") {
      config.max_receive_message_bytes = read_size(display_name, value, key);
      if (config.max_receive_message_bytes < (std::size_t{1} << 20) ||
          config.max_receive_message_bytes >
              static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw ConfigError(located(display_name, value, key) +
                          ": must be from 1MiB to 2GiB - 1 (gRPC's limit), got " +
                          scalar_text(value));
    } else if (key == "max_width") {
      config.limits.max_width =
          static_cast<std::uint32_t>(read_limit(display_name, value, key, kLargestDimension));
    } else if (key == "max_height") {
      config.limits.max_height =
          static_cast<std::uint32_t>(read_limit(display_name, value, key, kLargestDimension));
    } else if (key == "max_pixels") {
      config.limits.max_pixels = read_limit(display_name, value, key,
                                            std::uint64_t{kLargestDimension} * kLargestDimension);
    } else if (key == "max_samples_per_pixel") {
      config.limits.max_samples_per_pixel =
          static_cast<std::uint32_t>(read_limit(display_name, value, key, kLargestSamplesPerPixel));
    } else if (key == "max_primitives") {
      config.limits.max_primitives = read_limit(display_name, value, key, kLargestPrimitives);
      config.limits.max_triangles =
          std::max(config.limits.max_triangles, config.limits.max_primitives);
    } else if (key == "memory_budget") {
      config.memory_budget = value.IsScalar() && value.Scalar() == "auto"
                                 ? kMemoryBudgetAuto
                                 : read_size(display_name, value, key);
    } else if (key == "prepare_timeout") {
      config.prepare_timeout = read_duration(display_name, value, key);
    } else if (key == "tile_retries") {
      config.tile_retries = read_count(display_name, value, key);
      if (config.tile_retries > kMaxTileRetries)
        throw ConfigError(located(display_name, value, key) + ": must be from 0 to " +
                          std::to_string(kMaxTileRetries) + ", got " + scalar_text(value));
    } else if (key == "watch_buffer") {
      config.watch_buffer = read_count(display_name, value, key);
      if (config.watch_buffer < 1)
        throw ConfigError(located(display_name, value, key) + ": must be at least 1, got " +
                          scalar_text(value));
    } else if (key == "watch_write_timeout") {
      config.watch_write_timeout = read_duration(display_name, value, key);
      if (config.watch_write_timeout <= std::chrono::milliseconds(0))
        throw ConfigError(located(display_name, value, key) + ": must be longer than 0");
    } else if (key == "metrics_listen") {
      config.metrics_listen = read_string(display_name, value, key);
      if (!config.metrics_listen.empty()) {
        const auto listen = parse_listen_address(config.metrics_listen);
        if (const auto* problem = std::get_if<std::string>(&listen))
          throw ConfigError(located(display_name, value, key) + ": " + *problem);
      }
    } else if (key == "log_format") {
      config.log_format = read_string(display_name, value, key);
      if (!parse_log_format(config.log_format))
        throw ConfigError(located(display_name, value, key) + ": must be text or json, got '" +
                          config.log_format + "'");
    } else if (key == "tls_cert") {
      config.tls_cert = read_path(display_name, value, key);
    } else if (key == "tls_key") {
      config.tls_key = read_path(display_name, value, key);
    } else if (key == "tls_client_ca") {
      config.tls_client_ca = read_path(display_name, value, key);
    } else if (key == "allow_insecure_remote") {
      config.allow_insecure_remote = read_bool(display_name, value, key);
    } else if (key == "tokens") {
      config.tokens_file = read_path(display_name, value, key);
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace

DaemonConfig load_config_yaml(const std::string& text, const std::string& display_name,
                              DaemonConfig config, std::vector<std::string>& warnings) {
  const YAML::Node root = parse_yaml_document(text, display_name);
  if (!root.IsDefined() || root.IsNull()) return config;  // an empty file changes nothing
  if (!root.IsMap())
    throw ConfigError(display_name + ": must be a YAML map of settings (" + kKeys + ")");

  for (const auto& entry : root) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "?";
    if (!apply_setting(config, display_name, key, entry.second))
      warnings.push_back(located(display_name, entry.first, key) + ": unknown key, ignored");
  }
  return config;
}

DaemonConfig load_config_file(const std::filesystem::path& path, DaemonConfig base,
                              std::vector<std::string>& warnings) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path))
    throw ConfigError(path.string() + ": cannot read the config file");
  std::ostringstream text;
  text << in.rdbuf();
  return load_config_yaml(text.str(), path.string(), std::move(base), warnings);
}

}  // namespace tessera::server
