#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "client/cli_options.hpp"

namespace tessera {
namespace {

struct Parsed {
  ParsedCommandLine result;
  std::string out, err;
};

Parsed parse(std::vector<const char*> args) {
  args.insert(args.begin(), "tessera");
  std::ostringstream out, err;
  Parsed p{parse_command_line(static_cast<int>(args.size()), args.data(), out, err), {}, {}};
  p.out = out.str();
  p.err = err.str();
  return p;
}

TEST(CliOptions, RenderWithOverrides) {
  const Parsed p =
      parse({"render", "scene.yaml", "-o", "out/a.exr", "--png", "out/a.png", "--width", "64",
             "--height", "48", "--spp", "4", "--server", "localhost:6000"});
  ASSERT_TRUE(p.result.command) << p.err;
  const CliCommand& c = *p.result.command;
  EXPECT_EQ(c.kind, CommandKind::kRender);
  EXPECT_EQ(c.scene_path, "scene.yaml");
  EXPECT_EQ(c.output_exr, "out/a.exr");
  EXPECT_EQ(c.preview_png, "out/a.png");
  EXPECT_EQ(c.overrides.width, 64u);
  EXPECT_EQ(c.overrides.height, 48u);
  EXPECT_EQ(c.overrides.samples_per_pixel, 4u);
  EXPECT_FALSE(c.overrides.tile_size.has_value());
  EXPECT_FALSE(c.overrides.seed.has_value());
  EXPECT_EQ(c.server, "localhost:6000");
  EXPECT_FALSE(c.local);
}

TEST(CliOptions, PassesOverrideTheSceneForRenderAndSubmit) {
  Parsed p = parse({"render", "scene.yaml", "-o", "a.exr", "--passes", "4"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->overrides.passes, 4u);
  p = parse({"submit", "scene.yaml", "--passes", "2"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->overrides.passes, 2u);
  p = parse({"render", "scene.yaml", "-o", "a.exr"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_FALSE(p.result.command->overrides.passes.has_value());
  p = parse({"render", "scene.yaml", "-o", "a.exr", "--passes", "-1"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--passes"), std::string::npos) << p.err;
}

TEST(CliOptions, AccelBuilderOverridesTheSceneAndIsOneOfItsChoices) {
  Parsed p = parse({"render", "scene.yaml", "-o", "a.exr", "--accel-builder", "binned"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->overrides.accel_builder, "binned");
  p = parse({"submit", "scene.yaml", "--accel-builder", "spatial"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->overrides.accel_builder, "spatial");
  p = parse({"render", "scene.yaml", "-o", "a.exr"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_FALSE(p.result.command->overrides.accel_builder.has_value());
  p = parse({"render", "scene.yaml", "-o", "a.exr", "--accel-builder", "sbvh"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--accel-builder"), std::string::npos) << p.err;
}

TEST(CliOptions, DefaultsAndLocal) {
  const Parsed p = parse({"render", "scene.yaml", "-o", "a.exr", "--local", "--threads", "3"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_TRUE(p.result.command->local);
  EXPECT_EQ(p.result.command->threads, 3u);
  EXPECT_EQ(p.result.command->server, kDefaultServer);
  EXPECT_TRUE(p.result.command->preview_png.empty());
  EXPECT_FALSE(p.result.command->overrides.width.has_value());
}

TEST(CliOptions, OtherCommands) {
  Parsed p = parse({"submit", "s.yaml", "--name", "hello", "--priority", "-5"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kSubmit);
  EXPECT_EQ(p.result.command->name, "hello");
  EXPECT_EQ(p.result.command->priority, -5);

  p = parse({"watch", "job-1", "-o", "w.exr"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kWatch);
  EXPECT_EQ(p.result.command->job_id, "job-1");

  p = parse({"list", "--server", "[::1]:50051"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kList);

  p = parse({"status", "j"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kStatus);

  p = parse({"cancel", "j"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kCancel);
}

TEST(CliOptions, JobControlCommands) {
  Parsed p = parse({"pause", "job-1"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kPause);
  EXPECT_EQ(p.result.command->job_id, "job-1");
  p = parse({"resume", "job-1"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kResume);
  p = parse({"retry", "job-1"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kRetry);

  p = parse({"update", "job-1", "--priority", "-2", "--label", "shot=010", "--label", "a=b=c",
             "--remove-label", "old", "--submitter", "ana"});
  ASSERT_TRUE(p.result.command) << p.err;
  const CliCommand& u = *p.result.command;
  EXPECT_EQ(u.kind, CommandKind::kUpdate);
  EXPECT_EQ(u.new_priority, -2);
  EXPECT_EQ(u.labels, (std::vector<std::string>{"shot=010", "a=b=c"}));
  EXPECT_EQ(u.remove_labels, (std::vector<std::string>{"old"}));
  EXPECT_EQ(u.new_submitter, "ana");

  p = parse({"events", "--job", "job-1", "--label", "shot"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kEvents);
  EXPECT_EQ(p.result.command->job_id, "job-1");
  EXPECT_EQ(p.result.command->label_filter, "shot");

  p = parse({"list", "--label", "shot=010", "--name", "hero"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->label_filter, "shot=010");
  EXPECT_EQ(p.result.command->name_filter, "hero");

  p = parse({"submit", "s.yaml", "--label", "dept=fx"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->labels, (std::vector<std::string>{"dept=fx"}));
}

// Each bad invocation: no command, exit code 2, one line `tessera: ...` naming the problem.
void expect_usage_error(std::vector<const char*> args, const std::string& mentions) {
  const Parsed p = parse(args);
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
  EXPECT_EQ(p.err.rfind("tessera: ", 0), 0u) << p.err;
  EXPECT_EQ(std::count(p.err.begin(), p.err.end(), '\n'), 1) << p.err;
  EXPECT_NE(p.err.find(mentions), std::string::npos)
      << "expected '" << mentions << "' in: " << p.err;
}

TEST(CliOptions, RejectsBadArguments) {
  expect_usage_error({}, "no command");
  expect_usage_error({"paint"}, "paint");
  expect_usage_error({"render", "s.yaml"}, "--output");
  expect_usage_error({"render", "-o", "a.exr"}, "scene");
  expect_usage_error({"render", "s.yaml", "-o", "a.png"}, ".exr");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--png", "a.jpg"}, ".png");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--width", "0"}, "--width");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--height", "100000"}, "--height");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--spp", "-3"}, "--spp");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--spp", "many"}, "--spp");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--tile-size", "4"}, "--tile-size");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--threads", "4"}, "--local");
  expect_usage_error({"render", "s.yaml", "-o", "a.exr", "--server", "localhost"}, "no port");
  expect_usage_error({"list", "--server", "localhost:70000"}, "out of range");
  expect_usage_error({"list", "extra"}, "extra");
  expect_usage_error({"status"}, "job");
  expect_usage_error({"cancel", ""}, "empty");
  expect_usage_error({"pause"}, "job");
  expect_usage_error({"update", "job-1"}, "nothing to change");
  expect_usage_error({"update", "job-1", "--label", "novalue"}, "KEY=VALUE");
  expect_usage_error({"update", "job-1", "--priority", "high"}, "--priority");
  expect_usage_error({"submit", "s.yaml", "--label", "=x"}, "KEY=VALUE");
}

TEST(CliOptions, HelpGoesToStdoutWithExitZero) {
  const Parsed p = parse({"render", "--help"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, 0);
  EXPECT_NE(p.out.find("--spp"), std::string::npos) << p.out;
  EXPECT_TRUE(p.err.empty()) << p.err;
}

TEST(CliOptions, ServerAddressChecks) {
  EXPECT_FALSE(check_server_address("127.0.0.1:50051"));
  EXPECT_FALSE(check_server_address("render-host.example:1"));
  EXPECT_FALSE(check_server_address("[::1]:65535"));
  EXPECT_FALSE(check_server_address("unix:/run/tesserad.sock"));
  EXPECT_FALSE(check_server_address("dns:///render:50051"));
  EXPECT_TRUE(check_server_address(""));
  EXPECT_TRUE(check_server_address("host"));
  EXPECT_TRUE(check_server_address(":50051"));
  EXPECT_TRUE(check_server_address("host:"));
  EXPECT_TRUE(check_server_address("host:0"));
  EXPECT_TRUE(check_server_address("host:65536"));
  EXPECT_TRUE(check_server_address("host:12ab"));
  EXPECT_TRUE(check_server_address("::1:50051"));
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

Parsed parse_words(std::vector<const char*> args) {
  return parse(std::move(args));
}

TEST(CliScriptingOptions, VersionHealthAndTheirServer) {
  Parsed p = parse_words({"--version"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kVersion);
  p = parse_words({"--version", "--server", "render-box:7001"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kVersion);
  EXPECT_EQ(p.result.command->server, "render-box:7001");
  p = parse_words({"version", "--server", "render-box:7000"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kVersion);
  EXPECT_EQ(p.result.command->server, "render-box:7000");
  p = parse_words({"health", "--address", "127.0.0.1:6000"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kHealth);
  EXPECT_EQ(p.result.command->server, "127.0.0.1:6000");
  p = parse_words({"health", "--address", "no-port"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
}

TEST(CliScriptingOptions, JsonListFiltersStdoutAndInterruptFlags) {
  Parsed p = parse_words({"list", "--state", "running", "--limit", "5", "--json", "--label", "k"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->state_filter, "running");
  EXPECT_EQ(p.result.command->limit, 5u);
  EXPECT_TRUE(p.result.command->json);
  p = parse_words({"list", "--state", "sleeping"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--state"), std::string::npos) << p.err;
  p = parse_words({"list", "--limit", "0"});
  EXPECT_FALSE(p.result.command);

  p = parse_words({"render", "s.yaml", "-o", "-", "--keep-partial"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->output_exr, "-");
  EXPECT_TRUE(p.result.command->keep_partial);
  p = parse_words({"watch", "job-1", "-o", "-", "--cancel"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_TRUE(p.result.command->cancel_on_interrupt);
  p = parse_words({"watch", "job-1", "-o", "-", "--json"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--json and -o -"), std::string::npos) << p.err;
  p = parse_words({"render", "s.yaml", "-o", "image.png"});
  EXPECT_FALSE(p.result.command);
  for (const char* command : {"submit", "status", "list", "watch"}) {
    std::vector<const char*> args = {command};
    if (std::string(command) == "submit") args.push_back("s.yaml");
    if (std::string(command) == "status" || std::string(command) == "watch") args.push_back("j");
    if (std::string(command) == "watch") args.insert(args.end(), {"-o", "a.exr"});
    args.push_back("--json");
    p = parse_words(args);
    ASSERT_TRUE(p.result.command) << command << ": " << p.err;
    EXPECT_TRUE(p.result.command->json) << command;
  }
}

TEST(CliScriptingOptions, RequestIdIsCheckedBeforeAnythingIsSent) {
  Parsed p = parse_words({"submit", "s.yaml", "--request-id", "nightly-42"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->request_id, "nightly-42");
  p = parse_words({"render", "s.yaml", "-o", "a.exr", "--request-id", "r"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->request_id, "r");
  const std::string too_long(129, 'x');
  p = parse_words({"submit", "s.yaml", "--request-id", too_long.c_str()});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--request-id"), std::string::npos) << p.err;
}

TEST(CliScriptingOptions, UnknownCommandsAndFlagsGetADidYouMean) {
  Parsed p = parse_words({"rendr", "s.yaml"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
  EXPECT_NE(p.err.find("unknown command 'rendr' (did you mean 'render'?)"), std::string::npos)
      << p.err;
  p = parse_words({"render", "s.yaml", "-o", "a.exr", "--spd", "4"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("for '--spd' did you mean '--spp'?"), std::string::npos) << p.err;
  p = parse_words({"list", "--submiter=me"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("did you mean '--submitter'?"), std::string::npos) << p.err;
  p = parse_words({"list", "--zzzzzzzz"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.err.find("did you mean"), std::string::npos) << p.err;
}

const std::vector<std::string> kCommands = {
    "render", "submit", "watch",  "list",   "status",  "cancel",  "delete", "pause",
    "resume", "retry",  "update", "events", "denoise", "version", "health", "completion"};

TEST(CliScriptingOptions, BashCompletionIsValidBashWithEveryCommandAndFlag) {
  const Parsed p = parse_words({"completion", "bash"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitOk) << p.err;
  const std::filesystem::path script =
      std::filesystem::temp_directory_path() /
      ("tessera-completion-" + std::to_string(::getpid()) + ".bash");
  std::ofstream(script) << p.out;
  EXPECT_EQ(std::system(("bash -n " + script.string()).c_str()), 0) << p.out;
  // Sourced, it registers the completion without error.
  EXPECT_EQ(
      std::system(
          ("bash -c 'source " + script.string() + " && complete -p tessera > /dev/null'").c_str()),
      0);
  std::filesystem::remove(script);
  for (const std::string& command : kCommands) {
    EXPECT_NE(p.out.find(" " + command + ")"), std::string::npos) << command;
    EXPECT_NE(p.out.find(command), std::string::npos) << command;
  }
  for (const char* flag : {"--keep-partial", "--request-id", "--json", "--state", "--limit",
                           "--address", "--spp", "--server"})
    EXPECT_NE(p.out.find(flag), std::string::npos) << flag;
}

TEST(CliScriptingOptions, ZshCompletionNamesEveryCommand) {
  const Parsed p = parse_words({"completion", "zsh"});
  EXPECT_EQ(p.result.exit_code, kExitOk) << p.err;
  EXPECT_EQ(p.out.rfind("#compdef tessera\n", 0), 0u);
  for (const std::string& command : kCommands)
    EXPECT_NE(p.out.find("'" + command + ":"), std::string::npos) << command;
  EXPECT_NE(p.out.find("compdef _tessera tessera"), std::string::npos);
  // zsh is not a build dependency: its own syntax check runs where it is installed.
  if (std::filesystem::exists("/usr/bin/zsh")) {
    const std::filesystem::path script =
        std::filesystem::temp_directory_path() /
        ("tessera-completion-" + std::to_string(::getpid()) + ".zsh");
    std::ofstream(script) << p.out;
    EXPECT_EQ(std::system(("/usr/bin/zsh -n " + script.string()).c_str()), 0) << p.out;
    EXPECT_EQ(std::system(("/usr/bin/zsh -c 'autoload -U compinit && compinit -u -D && source " +
                           script.string() + " && [[ ${_comps[tessera]} == _tessera ]]'")
                              .c_str()),
              0);
    std::filesystem::remove(script);
  }
  const Parsed bad = parse_words({"completion", "fish"});
  EXPECT_EQ(bad.result.exit_code, kExitUsage);
}

}  // namespace
}  // namespace tessera
