#pragma once
// What the configuration tests share: tesserad's command line parsed from a list of
// arguments, and a folder per test to write configuration files into.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "server/command_line.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera::server::testing {

namespace detail {
inline std::vector<const char*> tesserad_argv(std::vector<std::string>& args) {
  args.insert(args.begin(), "tesserad");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  return argv;
}
}  // namespace detail

// `tesserad <args...>` parsed as tesserad parses it, with this process's environment.
inline CommandLine parse_tesserad(std::vector<std::string> args) {
  const std::vector<const char*> argv = detail::tesserad_argv(args);
  return parse_command_line(static_cast<int>(argv.size()), argv.data());
}

// The same with `environment` in place of this process's (tests stay independent of the
// TESSERAD_* variables of whoever runs them).
inline CommandLine parse_tesserad(std::vector<std::string> args, const Environment& environment) {
  const std::vector<const char*> argv = detail::tesserad_argv(args);
  return parse_command_line(static_cast<int>(argv.size()), argv.data(), environment);
}

// A fresh folder per test (removed after it) and `write`, which puts a configuration file
// in it.
class ConfigFileTest : public test::TestDirFixture {
 protected:
  ConfigFileTest() : TestDirFixture("tesserad") {}

  // Writes `text` as the folder's tesserad.yaml (replacing the last one) and returns its path.
  std::string write(const std::string& text) {
    const auto path = dir_ / "tesserad.yaml";
    std::ofstream(path) << text;
    return path.string();
  }
};

}  // namespace tessera::server::testing
