#pragma once
#include <ostream>

#include "client/cli_options.hpp"

namespace tessera {

// Where a command writes: results on `out`, progress and errors on `err`. `interactive`:
// `err` is a terminal, so progress is one line redrawn in place.
struct CommandOutput {
  std::ostream& out;
  std::ostream& err;
  bool interactive = false;
};

// Runs one parsed `tessera` command and returns the process exit code (kExitOk,
// kExitFailed, kExitUsage). Every failure is reported as one line `tessera: <message>` on
// `err`.
int run_command(const CliCommand& command, const CommandOutput& io);

}  // namespace tessera
