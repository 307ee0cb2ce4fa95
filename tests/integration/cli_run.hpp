#pragma once
// The CLI run in the test's own process, as `tessera` would run: a command line parsed and
// run, or an already parsed command run, with its exit code and what it wrote.
#include <sstream>
#include <string>
#include <vector>

#include "client/cli_options.hpp"
#include "client/commands.hpp"

namespace tessera::test {

struct CliRun {
  int exit_code;
  std::string out, err;
};

// Runs `command`, its standard output and error captured.
inline CliRun run_cli(const CliCommand& command) {
  std::ostringstream out, err;
  const int code = run_command(command, {out, err, false});
  return {code, out.str(), err.str()};
}

// `tessera ARGS...`: parsed as the command line is, then run; a command line that does not
// parse gives the parser's exit code and messages.
inline CliRun run_cli(std::vector<std::string> args) {
  args.insert(args.begin(), "tessera");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  std::ostringstream out, err;
  const ParsedCommandLine parsed =
      parse_command_line(static_cast<int>(argv.size()), argv.data(), out, err);
  if (!parsed.command) return {parsed.exit_code, out.str(), err.str()};
  return run_cli(*parsed.command);
}

}  // namespace tessera::test
