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
  std::vector<std::string> warnings;  // unknown keys and TESSERAD_* variables
  std::optional<int> exit_code;       // set: print `message` and exit with this code
  std::string message;                // for stdout when exit_code is 0, stderr otherwise
};

inline constexpr int kExitUsage = 2;

// Parses `tesserad [--listen HOST:PORT] [--threads N] [--data DIR] [--config FILE.yaml]
// [--log-level LEVEL] [--log-format text|json] [--metrics-listen HOST:PORT]
// [--tls-cert FILE --tls-key FILE [--tls-client-ca FILE]] [--allow-insecure-remote]
// [--tokens FILE] [--version] [--help]`. Settings come from the defaults, then the config
// file (--config, else $TESSERAD_CONFIG), then the TESSERAD_* environment variables, then
// the flags given explicitly; the result is validated.
CommandLine parse_command_line(int argc, const char* const argv[]);
// The same with an explicit environment instead of the process's (tests).
CommandLine parse_command_line(int argc, const char* const argv[], const Environment& environment);

}  // namespace tessera::server
