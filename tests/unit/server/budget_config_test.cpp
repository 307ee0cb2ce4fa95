// The budget keys of tesserad's configuration file: read with their units, bad values
// named, and the limits they set reach the scene checks.
#include <gtest/gtest.h>

#include "server/config.hpp"

namespace tessera::server {
namespace {

DaemonConfig load(const std::string& text) {
  std::vector<std::string> warnings;
  DaemonConfig config = load_config_yaml(text, "tesserad.yaml", DaemonConfig{}, warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  return config;
}

std::string error_of(const std::string& text) {
  try {
    load(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

TEST(BudgetConfig, SizesTakeBinaryAndDecimalUnits) {
  EXPECT_EQ(parse_size("1024"), 1024u);
  EXPECT_EQ(parse_size("512MiB"), std::size_t{512} << 20);
  EXPECT_EQ(parse_size("8GiB"), std::size_t{8} << 30);
  EXPECT_EQ(parse_size("1.5GiB"), std::size_t{3} << 29);
  EXPECT_EQ(parse_size("2 GB"), 2'000'000'000u);
  EXPECT_EQ(parse_size("64KB"), 64'000u);
  for (const char* bad : {"", "GiB", "-1GiB", "1.2.3", "12 parsecs", ".5GiB", "99999999999TiB"})
    EXPECT_FALSE(parse_size(bad)) << bad;
}

TEST(BudgetConfig, DefaultsSuitAFarmNode) {
  const DaemonConfig config;
  EXPECT_EQ(config.max_receive_message_bytes, std::size_t{256} << 20);
  EXPECT_EQ(config.limits.max_width, 16384u);
  EXPECT_EQ(config.limits.max_height, 16384u);
  EXPECT_EQ(config.limits.max_pixels, std::size_t{8192} * 8192);
  EXPECT_EQ(config.limits.max_samples_per_pixel, 65536u);
  EXPECT_EQ(config.limits.max_primitives, 50'000'000u);
  EXPECT_EQ(config.memory_budget, kMemoryBudgetAuto);
  EXPECT_EQ(config.prepare_timeout, std::chrono::minutes(10));
  // Auto: half the physical memory, which any machine running the tests has some of.
  EXPECT_GT(effective_memory_budget(config), std::size_t{64} << 20);
}

TEST(BudgetConfig, EveryBudgetKeyIsRead) {
  const DaemonConfig config = load(
      "max_receive_message_bytes: 64MiB\n"
      "max_width: 4096\n"
      "max_height: 2048\n"
      "max_pixels: 4000000\n"
      "max_samples_per_pixel: 1024\n"
      "max_primitives: 1000000\n"
      "memory_budget: 12GiB\n"
      "prepare_timeout: 90s\n");
  EXPECT_EQ(config.max_receive_message_bytes, std::size_t{64} << 20);
  EXPECT_EQ(config.limits.max_width, 4096u);
  EXPECT_EQ(config.limits.max_height, 2048u);
  EXPECT_EQ(config.limits.max_pixels, 4'000'000u);
  EXPECT_EQ(config.limits.max_samples_per_pixel, 1024u);
  EXPECT_EQ(config.limits.max_primitives, 1'000'000u);
  EXPECT_EQ(config.memory_budget, std::size_t{12} << 30);
  EXPECT_EQ(config.prepare_timeout, std::chrono::seconds(90));
  EXPECT_EQ(effective_memory_budget(config), std::size_t{12} << 30);
  EXPECT_NO_THROW(validate_config(config));
  EXPECT_EQ(load("memory_budget: auto\n").memory_budget, kMemoryBudgetAuto);
  EXPECT_EQ(effective_memory_budget(load("memory_budget: 0\n")), 0u);  // no limit
  EXPECT_EQ(load("prepare_timeout: 0\n").prepare_timeout.count(), 0);  // no limit
}

TEST(BudgetConfig, BadValuesNameTheKey) {
  EXPECT_NE(error_of("max_width: 0\n")
                .find("tesserad.yaml:1: max_width: must be a whole number "
                      "from 1 to 65536"),
            std::string::npos);
  EXPECT_NE(error_of("max_samples_per_pixel: 100000\n").find("max_samples_per_pixel"),
            std::string::npos);
  EXPECT_NE(error_of("max_primitives: 1000000000\n").find("max_primitives"), std::string::npos);
  EXPECT_NE(error_of("memory_budget: lots\n").find("memory_budget: must be a size"),
            std::string::npos);
  EXPECT_NE(error_of("max_receive_message_bytes: 1KiB\n").find("max_receive_message_bytes"),
            std::string::npos);
  EXPECT_NE(error_of("max_receive_message_bytes: 4GiB\n").find("gRPC's limit"), std::string::npos);
  EXPECT_NE(error_of("prepare_timeout: soon\n").find("prepare_timeout: must be a duration"),
            std::string::npos);
}

TEST(BudgetConfig, ValidateConfigChecksLimitsSetInCode) {
  DaemonConfig config;
  config.limits.max_width = 0;
  EXPECT_THROW(validate_config(config), ConfigError);
  config = DaemonConfig{};
  config.limits.max_samples_per_pixel = 70000;
  EXPECT_THROW(validate_config(config), ConfigError);
  config = DaemonConfig{};
  config.max_receive_message_bytes = std::size_t{3} << 30;
  EXPECT_THROW(validate_config(config), ConfigError);
}

}  // namespace
}  // namespace tessera::server
