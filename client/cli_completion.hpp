#pragma once
#include <CLI/CLI.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace tessera {

// The shells `tessera completion` writes scripts for.
inline const std::vector<std::string>& completion_shells() {
  static const std::vector<std::string> shells = {"bash", "zsh"};
  return shells;
}

// A completion script for `shell` (bash or zsh) completing the subcommands of `app` and the
// flags of each, read from the app itself so the script cannot drift from the parser.
// `program` is the command's name.
std::string completion_script(const CLI::App& app, std::string_view shell,
                              std::string_view program);

// Every flag spelling of `command` ("-o", "--output", ...), positionals left out.
std::vector<std::string> flag_names(const CLI::App& command);

}  // namespace tessera
