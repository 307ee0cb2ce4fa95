// TESSERAD_* environment variables: every key has one, derived from its name; the order of
// precedence is flags over environment over file over defaults; bad values name the
// variable.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "config_fixture.hpp"
#include "server/command_line.hpp"
#include "server/config.hpp"

namespace tessera::server {
namespace {

using testing::parse_tesserad;

class EnvironmentConfigFile : public testing::ConfigFileTest {};

TEST(EnvironmentVariableNames, AreDerivedFromTheKeys) {
  EXPECT_EQ(environment_variable_for("listen"), "TESSERAD_LISTEN");
  EXPECT_EQ(environment_variable_for("max_pixels"), "TESSERAD_MAX_PIXELS");
  EXPECT_EQ(environment_variable_for("metrics_listen"), "TESSERAD_METRICS_LISTEN");
}

TEST(EnvironmentConfig, EveryKindOfSettingIsRead) {
  std::vector<std::string> warnings;
  const DaemonConfig config = apply_environment({{"TESSERAD_LISTEN", "0.0.0.0:7000"},
                                                 {"TESSERAD_THREADS", "3"},
                                                 {"TESSERAD_DATA", "/srv/t"},
                                                 {"TESSERAD_MAX_PIXELS", "1000000"},
                                                 {"TESSERAD_MEMORY_BUDGET", "2GiB"},
                                                 {"TESSERAD_JOB_TTL", "12h"},
                                                 {"TESSERAD_LOG_FORMAT", "json"},
                                                 {"TESSERAD_METRICS_LISTEN", "127.0.0.1:9100"},
                                                 {"HOME", "/root"}},
                                                DaemonConfig{}, warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(config.listen, "0.0.0.0:7000");
  EXPECT_EQ(config.threads, 3u);
  EXPECT_EQ(config.data_dir, std::filesystem::path("/srv/t"));
  EXPECT_EQ(config.limits.max_pixels, 1000000u);
  EXPECT_EQ(config.memory_budget, std::size_t{2} << 30);
  EXPECT_EQ(config.job_ttl, std::chrono::hours(12));
  EXPECT_EQ(config.log_format, "json");
  EXPECT_EQ(config.metrics_listen, "127.0.0.1:9100");
}

TEST(EnvironmentConfig, BadValuesNameTheVariable) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"TESSERAD_THREADS", "lots"},     {"TESSERAD_THREADS", "0"},
      {"TESSERAD_LISTEN", "nowhere"},   {"TESSERAD_MAX_PIXELS", "-5"},
      {"TESSERAD_JOB_TTL", "soon"},     {"TESSERAD_MEMORY_BUDGET", "lots"},
      {"TESSERAD_LOG_FORMAT", "xml"},   {"TESSERAD_METRICS_LISTEN", "9100"},
      {"TESSERAD_LOG_LEVEL", "chatty"},
  };
  for (const auto& [name, value] : cases) {
    std::vector<std::string> warnings;
    try {
      apply_environment({{name, value}}, DaemonConfig{}, warnings);
      ADD_FAILURE() << name << "=" << value << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name + ": ", 0), 0u) << e.what();
    }
  }
}

TEST(EnvironmentConfig, UnknownVariablesWarnAndEmptyOnesAreUnset) {
  std::vector<std::string> warnings;
  const DaemonConfig config = apply_environment(
      {{"TESSERAD_THREDS", "4"}, {"TESSERAD_threads", "4"}, {"TESSERAD_THREADS", ""}},
      DaemonConfig{}, warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("TESSERAD_THREDS"), std::string::npos);
  EXPECT_NE(warnings[1].find("TESSERAD_threads"), std::string::npos);
  EXPECT_EQ(config.threads, default_thread_count());
}

TEST_F(EnvironmentConfigFile, FlagsOverrideTheEnvironmentWhichOverridesTheFile) {
  const std::string file = write("threads: 5\nlisten: 127.0.0.1:6000\nlog_level: warn\n");
  const Environment environment = {{"TESSERAD_THREADS", "6"}, {"TESSERAD_LOG_LEVEL", "debug"}};

  const CommandLine env_over_file = parse_tesserad({"--config", file}, environment);
  ASSERT_FALSE(env_over_file.exit_code) << env_over_file.message;
  EXPECT_EQ(env_over_file.config.threads, 6u);               // environment over file
  EXPECT_EQ(env_over_file.config.listen, "127.0.0.1:6000");  // file over default
  EXPECT_EQ(env_over_file.config.log_level, "debug");

  const CommandLine flags_over_env =
      parse_tesserad({"--config", file, "--threads", "7", "--log-level", "error"}, environment);
  ASSERT_FALSE(flags_over_env.exit_code) << flags_over_env.message;
  EXPECT_EQ(flags_over_env.config.threads, 7u);
  EXPECT_EQ(flags_over_env.config.log_level, "error");
  EXPECT_EQ(flags_over_env.config.listen, "127.0.0.1:6000");
}

TEST_F(EnvironmentConfigFile, TesseradConfigNamesTheFileUnlessAFlagDoes) {
  const std::string file = write("threads: 5\n");
  const CommandLine from_variable = parse_tesserad({}, {{"TESSERAD_CONFIG", file}});
  ASSERT_FALSE(from_variable.exit_code) << from_variable.message;
  EXPECT_EQ(from_variable.config.threads, 5u);

  const std::string other = (dir_ / "other.yaml").string();
  std::ofstream(other) << "threads: 2\n";
  const CommandLine flag_wins = parse_tesserad({"--config", other}, {{"TESSERAD_CONFIG", file}});
  ASSERT_FALSE(flag_wins.exit_code) << flag_wins.message;
  EXPECT_EQ(flag_wins.config.threads, 2u);
}

TEST(EnvironmentConfig, ABadVariableIsAUsageErrorOfTheCommandLine) {
  const CommandLine cl = parse_tesserad({}, {{"TESSERAD_MAX_PIXELS", "many"}});
  ASSERT_TRUE(cl.exit_code);
  EXPECT_EQ(*cl.exit_code, kExitUsage);
  EXPECT_NE(cl.message.find("TESSERAD_MAX_PIXELS: must be"), std::string::npos) << cl.message;
}

TEST(CommandLineObservability, MetricsAndLogFormatFlags) {
  const CommandLine cl =
      parse_tesserad({"--metrics-listen", "127.0.0.1:0", "--log-format", "json"}, {});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.metrics_listen, "127.0.0.1:0");
  EXPECT_EQ(cl.config.log_format, "json");
  const CommandLine defaults = parse_tesserad({}, {});
  EXPECT_EQ(defaults.config.metrics_listen, "");
  EXPECT_EQ(defaults.config.log_format, "text");
  for (const auto& bad : std::vector<std::vector<std::string>>{{"--log-format", "xml"},
                                                               {"--metrics-listen", "9100"}}) {
    const CommandLine refused = parse_tesserad(bad, {});
    ASSERT_TRUE(refused.exit_code) << bad[0];
    EXPECT_NE(refused.message.find(bad[0]), std::string::npos) << refused.message;
  }
}

}  // namespace
}  // namespace tessera::server
