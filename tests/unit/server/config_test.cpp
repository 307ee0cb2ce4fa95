#include "server/config.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <variant>

#include "config_fixture.hpp"
#include "server/command_line.hpp"
#include "server/listen_address.hpp"

namespace tessera::server {
namespace {

using testing::parse_tesserad;

class ConfigFile : public testing::ConfigFileTest {};

TEST(ListenAddress, AcceptsHostsAndPorts) {
  const auto a = std::get<ListenAddress>(parse_listen_address("127.0.0.1:50051"));
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.port, 50051);
  EXPECT_EQ(std::get<ListenAddress>(parse_listen_address("localhost:0")).port, 0);
  EXPECT_EQ(std::get<ListenAddress>(parse_listen_address("[::1]:65535")).host, "[::1]");
  EXPECT_EQ(std::get<ListenAddress>(parse_listen_address("0.0.0.0:8080")).to_string(),
            "0.0.0.0:8080");
}

TEST(ListenAddress, RejectsMalformedAddresses) {
  for (const char* bad : {"", "50051", "localhost", ":50051", "host:", "host:65536", "host:-1",
                          "host:12a", "::1:50051", "[::1:50051", "ho st:1", "host:1234567"}) {
    const auto parsed = parse_listen_address(bad);
    EXPECT_TRUE(std::holds_alternative<std::string>(parsed)) << "accepted '" << bad << "'";
  }
}

TEST(CommandLine, DefaultsWithoutFlags) {
  const CommandLine cl = parse_tesserad({});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.listen, "127.0.0.1:50051");
  EXPECT_EQ(cl.config.threads, default_thread_count());
  EXPECT_GE(cl.config.threads, 1u);
  EXPECT_EQ(cl.config.data_dir, std::filesystem::path("./var"));
  EXPECT_EQ(cl.config.log_level, "info");
}

TEST(CommandLine, FlagsSetEverySetting) {
  const CommandLine cl =
      parse_tesserad({"--listen", "0.0.0.0:0", "--threads", "3", "--data", "/tmp/x", "--log-level",
                      "debug", "--allow-insecure-remote"});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.listen, "0.0.0.0:0");
  EXPECT_EQ(cl.config.threads, 3u);
  EXPECT_EQ(cl.config.data_dir, std::filesystem::path("/tmp/x"));
  EXPECT_EQ(cl.config.log_level, "debug");
}

TEST(CommandLine, VersionAndHelpExitZero) {
  const CommandLine version = parse_tesserad({"--version"});
  ASSERT_TRUE(version.exit_code);
  EXPECT_EQ(*version.exit_code, 0);
  EXPECT_EQ(version.message, std::string("tesserad ") + TESSERA_VERSION + "\n");
  const CommandLine help = parse_tesserad({"--help"});
  ASSERT_TRUE(help.exit_code);
  EXPECT_EQ(*help.exit_code, 0);
  EXPECT_NE(help.message.find("--listen"), std::string::npos);
  EXPECT_NE(help.message.find("--threads"), std::string::npos);
}

TEST(CommandLine, BadFlagsAreUsageErrorsNamingTheFlag) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--threads", "0"}, "--threads"},
      {{"--threads", "lots"}, "--threads"},
      {{"--listen", "nowhere"}, "--listen"},
      {{"--listen", "host:99999"}, "--listen"},
      {{"--log-level", "chatty"}, "--log-level"},
      {{"--frobnicate"}, "--frobnicate"},
      {{"--data", ""}, "--data"},
  };
  for (const auto& [args, flag] : cases) {
    const CommandLine cl = parse_tesserad(args);
    ASSERT_TRUE(cl.exit_code) << args[0];
    EXPECT_EQ(*cl.exit_code, kExitUsage);
    EXPECT_NE(cl.message.find(flag), std::string::npos) << cl.message;
  }
}

TEST_F(ConfigFile, FileSetsValuesAndFlagsOverrideThem) {
  const std::string path = write(
      "listen: 0.0.0.0:6000\n"
      "allow_insecure_remote: true\n"
      "threads: 5\n"
      "data: /srv/tessera\n"
      "log_level: warn\n");
  const CommandLine from_file = parse_tesserad({"--config", path});
  ASSERT_FALSE(from_file.exit_code) << from_file.message;
  EXPECT_EQ(from_file.config.listen, "0.0.0.0:6000");
  EXPECT_EQ(from_file.config.threads, 5u);
  EXPECT_EQ(from_file.config.data_dir, std::filesystem::path("/srv/tessera"));
  EXPECT_EQ(from_file.config.log_level, "warn");
  EXPECT_TRUE(from_file.warnings.empty());

  const CommandLine overridden =
      parse_tesserad({"--threads", "2", "--config", path, "--listen", "127.0.0.1:7"});
  ASSERT_FALSE(overridden.exit_code) << overridden.message;
  EXPECT_EQ(overridden.config.threads, 2u);
  EXPECT_EQ(overridden.config.listen, "127.0.0.1:7");
  EXPECT_EQ(overridden.config.data_dir, std::filesystem::path("/srv/tessera"));  // from the file
  EXPECT_EQ(overridden.config.log_level, "warn");
}

TEST_F(ConfigFile, ShutdownGraceAndRetentionAreRead) {
  const CommandLine defaults = parse_tesserad({});
  ASSERT_FALSE(defaults.exit_code) << defaults.message;
  EXPECT_EQ(defaults.config.shutdown_grace, std::chrono::seconds(5));
  EXPECT_EQ(defaults.config.job_ttl, std::chrono::hours(7 * 24));
  EXPECT_EQ(defaults.config.max_jobs, 10000u);

  const CommandLine cl =
      parse_tesserad({"--config", write("shutdown_grace: 1500ms\njob_ttl: 12h\nmax_jobs: "
                                        "0\nmax_jobs_per_submitter: 7\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.shutdown_grace, std::chrono::milliseconds(1500));
  EXPECT_EQ(cl.config.job_ttl, std::chrono::hours(12));
  EXPECT_EQ(cl.config.max_jobs, 0u);
  EXPECT_EQ(cl.config.max_jobs_per_submitter, 7u);
  EXPECT_EQ(defaults.config.max_jobs_per_submitter, 1000u);
  EXPECT_TRUE(cl.warnings.empty());
}

TEST_F(ConfigFile, StreamWriteTimeoutIsReadWithItsDefault) {
  EXPECT_EQ(parse_tesserad({}).config.stream_write_timeout, std::chrono::seconds(30));
  const CommandLine cl = parse_tesserad({"--config", write("stream_write_timeout: 2m\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.stream_write_timeout, std::chrono::minutes(2));
  EXPECT_TRUE(cl.warnings.empty());
}

TEST_F(ConfigFile, GpusDefaultToAllAndCanBeTurnedOff) {
  EXPECT_TRUE(parse_tesserad({}).config.gpus);
  const CommandLine cl = parse_tesserad({"--config", write("gpus: none\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_FALSE(cl.config.gpus);
  EXPECT_TRUE(cl.warnings.empty());
}

TEST_F(ConfigFile, GpuBatchPixelsDefaultToTheDevicesOwnSize) {
  EXPECT_EQ(parse_tesserad({}).config.gpu_batch_pixels, 0u);
  const CommandLine cl = parse_tesserad({"--config", write("gpu_batch_pixels: 262144\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.gpu_batch_pixels, 262144u);
  EXPECT_TRUE(cl.warnings.empty());
}

TEST_F(ConfigFile, TileRetriesAndWatchSettingsAreRead) {
  const CommandLine defaults = parse_tesserad({});
  ASSERT_FALSE(defaults.exit_code) << defaults.message;
  EXPECT_EQ(defaults.config.tile_retries, 2u);
  EXPECT_EQ(defaults.config.watch_buffer, 1024u);
  EXPECT_EQ(defaults.config.watch_write_timeout, std::chrono::seconds(10));

  const CommandLine cl = parse_tesserad(
      {"--config", write("tile_retries: 0\nwatch_buffer: 16\nwatch_write_timeout: 250ms\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.tile_retries, 0u);
  EXPECT_EQ(cl.config.watch_buffer, 16u);
  EXPECT_EQ(cl.config.watch_write_timeout, std::chrono::milliseconds(250));
  EXPECT_TRUE(cl.warnings.empty());

  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {"tile_retries: 101\n", "tile_retries"},
           {"tile_retries: -1\n", "tile_retries"},
           {"watch_buffer: 0\n", "watch_buffer"},
           {"watch_write_timeout: 0s\n", "watch_write_timeout"}}) {
    const CommandLine bad = parse_tesserad({"--config", write(text)});
    ASSERT_TRUE(bad.exit_code) << text;
    EXPECT_NE(bad.message.find(key), std::string::npos) << bad.message;
  }
}

TEST(ParseDuration, AcceptsANumberWithAUnit) {
  EXPECT_EQ(parse_duration("250ms"), std::chrono::milliseconds(250));
  EXPECT_EQ(parse_duration("30"), std::chrono::seconds(30));
  EXPECT_EQ(parse_duration("30s"), std::chrono::seconds(30));
  EXPECT_EQ(parse_duration("15m"), std::chrono::minutes(15));
  EXPECT_EQ(parse_duration("2d"), std::chrono::hours(48));
  EXPECT_EQ(parse_duration("0"), std::chrono::milliseconds(0));
  for (const char* bad : {"", "s", "-1s", "1.5s", "1 s", "3y", "99999999999d", "1s2"})
    EXPECT_FALSE(parse_duration(bad)) << bad;
}

TEST_F(ConfigFile, UnknownKeysWarnWithTheirLine) {
  const CommandLine cl = parse_tesserad({"--config", write("threads: 2\nworkers: 9\n")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.threads, 2u);
  ASSERT_EQ(cl.warnings.size(), 1u);
  EXPECT_NE(cl.warnings[0].find(":2: workers: unknown key"), std::string::npos) << cl.warnings[0];
}

TEST_F(ConfigFile, BadValuesNameTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"threads: 0\n", ":1: threads: must be an integer from 1 to 1024, got '0'"},
      {"threads: many\n", "threads: must be an integer"},
      {"threads: [1, 2]\n", "threads: must be an integer from 1 to 1024, got a list"},
      {"listen: nowhere\n", "listen: must be HOST:PORT"},
      {"listen: {a: 1}\n", "listen: must be a string, got a map"},
      {"log_level: chatty\n", "log_level: must be one of"},
      {"data: ''\n", "data: must not be empty"},
      {"- just\n- a list\n", "must be a YAML map"},
      {"threads: [1\n", "YAML syntax error"},
      {"shutdown_grace: soon\n", ":1: shutdown_grace: must be a duration such as 30s"},
      {"job_ttl: -1d\n", "job_ttl: must be a duration"},
      {"job_ttl: 5w\n", "job_ttl: must be a duration"},
      {"max_jobs: -3\n", "max_jobs: must be a whole number, 0 for no limit, got '-3'"},
      {"max_jobs: lots\n", "max_jobs: must be a whole number"},
      {"stream_write_timeout: 0s\n", ":1: stream_write_timeout: must be at least 1ms, got '0s'"},
      {"stream_write_timeout: never\n", "stream_write_timeout: must be a duration"},
      {"gpus: some\n", ":1: gpus: must be all or none, got 'some'"},
      {"gpu_batch_pixels: -1\n", ":1: gpu_batch_pixels: must be a whole number from 0"},
      {"gpu_batch_pixels: 67108865\n",
       "gpu_batch_pixels: must be a whole number from 0 (the "
       "device's own size) to 67108864, got '67108865'"},
      {"gpu_batch_pixels: many\n", "gpu_batch_pixels: must be a whole number"},
  };
  for (const auto& [text, expected] : cases) {
    const CommandLine cl = parse_tesserad({"--config", write(text)});
    ASSERT_TRUE(cl.exit_code) << text;
    EXPECT_EQ(*cl.exit_code, kExitUsage);
    EXPECT_NE(cl.message.find(expected), std::string::npos)
        << "for " << text << "got " << cl.message;
  }
}

TEST_F(ConfigFile, AMissingFileIsAnError) {
  const CommandLine cl = parse_tesserad({"--config", (dir_ / "absent.yaml").string()});
  ASSERT_TRUE(cl.exit_code);
  EXPECT_NE(cl.message.find("cannot read the config file"), std::string::npos) << cl.message;
}

TEST_F(ConfigFile, AnEmptyFileChangesNothing) {
  const CommandLine cl = parse_tesserad({"--config", write("")});
  ASSERT_FALSE(cl.exit_code) << cl.message;
  EXPECT_EQ(cl.config.listen, kDefaultListen);
}

TEST(ValidateConfig, NamesTheBadSetting) {
  DaemonConfig config;
  config.threads = 0;
  EXPECT_THROW(
      {
        try {
          validate_config(config);
        } catch (const ConfigError& e) {
          EXPECT_EQ(std::string(e.what()).rfind("threads:", 0), 0u) << e.what();
          throw;
        }
      },
      ConfigError);
  config = DaemonConfig{};
  config.listen = "bad";
  EXPECT_THROW(validate_config(config), ConfigError);
  config = DaemonConfig{};
  config.log_level = "loud";
  EXPECT_THROW(validate_config(config), ConfigError);
  config = DaemonConfig{};
  config.stream_write_timeout = std::chrono::milliseconds(0);
  EXPECT_THROW(validate_config(config), ConfigError);
  EXPECT_NO_THROW(validate_config(DaemonConfig{}));
}

}  // namespace
}  // namespace tessera::server
