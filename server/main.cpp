// tesserad: parse the configuration, run a Daemon until SIGINT or SIGTERM, shut down cleanly.
#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <exception>

#include "server/command_line.hpp"
#include "server/daemon.hpp"
#include "server/structured_log.hpp"
#include "tessera/image/image_codecs.hpp"

int main(int argc, char** argv) {
  using namespace tessera::server;
  const CommandLine command_line = parse_command_line(argc, argv);
  if (command_line.exit_code) {
    std::fputs(command_line.message.c_str(), *command_line.exit_code == 0 ? stdout : stderr);
    return *command_line.exit_code;
  }
  const DaemonConfig& config = command_line.config;

  // Logs go to stderr so stdout carries only the "listening on" line scripts wait for.
  configure_logging(*parse_log_format(config.log_format), *parse_log_level(config.log_level));
  for (const std::string& warning : command_line.warnings) spdlog::warn("{}", warning);

  // Block the shutdown signals before any thread exists, so every thread inherits the
  // mask and the signals are only ever taken by sigwait below.
  sigset_t shutdown_signals;
  sigemptyset(&shutdown_signals);
  sigaddset(&shutdown_signals, SIGINT);
  sigaddset(&shutdown_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &shutdown_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  try {
    // Jobs write EXR tiles through the image codecs module: a daemon that cannot load it
    // refuses to start rather than failing every job.
    spdlog::debug("image codecs: {}", tessera::load_image_codecs().string());
    Daemon daemon(config);
    const int port = daemon.start();
    std::printf("tesserad listening on %s (port %d)\n", daemon.address().c_str(), port);
    std::fflush(stdout);

    int signal_number = 0;
    sigwait(&shutdown_signals, &signal_number);
    spdlog::info("received {}, shutting down", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    daemon.shutdown();
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
  return 0;
}
