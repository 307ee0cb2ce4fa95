#include "server/command_line.hpp"

#include <CLI/CLI.hpp>

#include <sstream>
#include <variant>

#include "server/listen_address.hpp"

namespace tessera::server {
namespace {

CLI::Validator listen_address_validator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        const auto parsed = parse_listen_address(value);
        if (const auto* problem = std::get_if<std::string>(&parsed)) return *problem;
        return {};
      },
      "");
}

CLI::Validator log_level_validator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        if (parse_log_level(value)) return {};
        return "must be one of trace, debug, info, warn, error, critical or off, got '" + value +
               "'";
      },
      "");
}

}  // namespace

CommandLine parse_command_line(int argc, const char* const argv[]) {
  return parse_command_line(argc, argv, process_environment());
}

CommandLine parse_command_line(int argc, const char* const argv[], const Environment& environment) {
  CommandLine result;
  DaemonConfig defaults;
  defaults.data_dir = kDefaultDataDir;

  std::string listen = defaults.listen;
  unsigned threads = defaults.threads;
  std::string data = defaults.data_dir.string();
  std::string log_level = defaults.log_level;
  std::string log_format = defaults.log_format;
  std::string metrics_listen;
  std::string config_file;

  CLI::App app(
      "tesserad: the Tessera render daemon. Takes scenes over gRPC "
      "(tessera.v1.RenderService), renders them tile by tile on every core and "
      "streams the tiles back as EXR.",
      "tesserad");
  app.set_version_flag("--version", std::string("tesserad ") + TESSERA_VERSION);
  CLI::Option* listen_opt =
      app.add_option("--listen", listen, "address to serve on; port 0 picks a free port")
          ->type_name("HOST:PORT")
          ->check(listen_address_validator())
          ->default_str(defaults.listen);
  CLI::Option* threads_opt = app.add_option("--threads", threads, "render worker threads")
                                 ->type_name("N")
                                 ->check(CLI::Range(1u, kMaxThreads))
                                 ->default_str(std::to_string(defaults.threads));
  CLI::Option* data_opt = app.add_option("--data", data, "data directory, created if missing")
                              ->type_name("DIR")
                              ->default_str(data);
  app.add_option("--config", config_file,
                 "YAML file with listen, threads, gpus, gpu_batch_pixels, data, log_level, "
                 "log_format, metrics_listen, "
                 "shutdown_grace, job_ttl, max_jobs, max_jobs_per_submitter and the budgets "
                 "(max_receive_message_bytes, max_width, max_height, max_pixels, "
                 "max_samples_per_pixel, max_primitives, memory_budget, prepare_timeout) and "
                 "stream_write_timeout and the security settings (tls_cert, tls_key, "
                 "tls_client_ca, allow_insecure_remote, tokens) (default: $TESSERAD_CONFIG). "
                 "Every key can also be set "
                 "as TESSERAD_<KEY> (TESSERAD_MAX_PIXELS); flags override the environment, "
                 "which overrides the file")
      ->type_name("FILE");
  std::string tls_cert, tls_key, tls_client_ca, tokens_file;
  CLI::Option* tls_cert_opt =
      app.add_option("--tls-cert", tls_cert, "server certificate chain (PEM); serve TLS")
          ->type_name("FILE");
  CLI::Option* tls_key_opt =
      app.add_option("--tls-key", tls_key, "the certificate's private key (PEM, unencrypted)")
          ->type_name("FILE");
  CLI::Option* tls_client_ca_opt =
      app.add_option("--tls-client-ca", tls_client_ca,
                     "require client certificates signed by this CA (PEM): mutual TLS")
          ->type_name("FILE");
  bool allow_insecure_remote = false;
  CLI::Option* insecure_opt =
      app.add_flag("--allow-insecure-remote", allow_insecure_remote,
                   "serve plaintext on an address other than loopback (refused without this)");
  CLI::Option* tokens_opt =
      app.add_option("--tokens", tokens_file,
                     "YAML list of bearer tokens {name, sha256, role}; every RenderService "
                     "call then needs one")
          ->type_name("FILE");
  CLI::Option* log_opt =
      app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
          ->type_name("LEVEL")
          ->check(log_level_validator())
          ->default_str(defaults.log_level);
  CLI::Option* format_opt =
      app.add_option("--log-format", log_format, "text, or json: one JSON object per line")
          ->type_name("FORMAT")
          ->check(CLI::IsMember({"text", "json"}))
          ->default_str(defaults.log_format);
  CLI::Option* metrics_opt =
      app.add_option("--metrics-listen", metrics_listen,
                     "serve Prometheus metrics at http://HOST:PORT/metrics (default: off)")
          ->type_name("HOST:PORT")
          ->check(listen_address_validator());

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::ostringstream out, err;
    const int code = app.exit(e, out, err);
    result.exit_code = code == 0 ? 0 : kExitUsage;
    result.message = code == 0 ? out.str() : err.str();
    return result;
  }

  try {
    // Precedence: defaults, then the file, then the environment, then the flags.
    DaemonConfig config = defaults;
    if (config_file.empty())
      for (const auto& [name, value] : environment)
        if (name == kConfigFileVariable) config_file = value;
    if (!config_file.empty()) config = load_config_file(config_file, config, result.warnings);
    config = apply_environment(environment, std::move(config), result.warnings);
    if (listen_opt->count() > 0) config.listen = listen;
    if (threads_opt->count() > 0) config.threads = threads;
    if (data_opt->count() > 0) {
      if (data.empty()) throw ConfigError("--data: must not be empty");
      config.data_dir = data;
    }
    if (log_opt->count() > 0) config.log_level = log_level;
    if (format_opt->count() > 0) config.log_format = log_format;
    if (metrics_opt->count() > 0) config.metrics_listen = metrics_listen;
    const auto path_flag = [](const CLI::Option* option, const std::string& value,
                              std::filesystem::path& setting) {
      if (option->count() == 0) return;
      if (value.empty()) throw ConfigError(option->get_name() + ": must not be empty");
      setting = value;
    };
    path_flag(tls_cert_opt, tls_cert, config.tls_cert);
    path_flag(tls_key_opt, tls_key, config.tls_key);
    path_flag(tls_client_ca_opt, tls_client_ca, config.tls_client_ca);
    path_flag(tokens_opt, tokens_file, config.tokens_file);
    if (insecure_opt->count() > 0) config.allow_insecure_remote = allow_insecure_remote;
    validate_config(config);
    result.config = std::move(config);
  } catch (const ConfigError& e) {
    result.exit_code = kExitUsage;
    result.message = std::string("tesserad: ") + e.what() + "\n";
  }
  return result;
}

}  // namespace tessera::server
