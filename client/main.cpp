// tessera: the command-line client of tesserad. See `tessera --help`.
#include <iostream>

#include "client/cli_options.hpp"
#include "client/commands.hpp"
#include "client/progress.hpp"

int main(int argc, char** argv) {
  const tessera::ParsedCommandLine parsed =
      tessera::parse_command_line(argc, argv, std::cout, std::cerr);
  if (!parsed.command) return parsed.exit_code;
  return tessera::run_command(*parsed.command,
                              {std::cout, std::cerr, tessera::stderr_is_terminal()});
}
