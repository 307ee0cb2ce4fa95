#pragma once
#include <optional>
#include <string>
#include <vector>

#include "server/config.hpp"

namespace tessera::server {

// What tesserad's command line asks for: a configuration to run with, or an exit
// (--help, --version, a bad flag or setting) with the text to print.
struct CommandLine {
  DaemonConfig config;
  std::vector<std::string> warnings;  // from the config file: unknown keys
  std::optional<int> exit_code;       // set: print `message` and exit with this code
  std::string message;                // for stdout when exit_code is 0, stderr otherwise
};

inline constexpr int kExitUsage = 2;

// Parses `tesserad [--listen HOST:PORT] [--threads N] [--data DIR] [--config FILE.yaml]
// [--log-level LEVEL] [--tls-cert FILE --tls-key FILE [--tls-client-ca FILE]]
// [--allow-insecure-remote] [--tokens FILE] [--version] [--help]`. Settings come from the defaults,
// then the config file, then the flags given explicitly; the result is validated.
CommandLine parse_command_line(int argc, const char* const argv[]);

}  // namespace tessera::server
