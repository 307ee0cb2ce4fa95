// The JSON log format: one object per line, whatever bytes the logged text and fields hold;
// structured fields appear only on their own event's line.
#include "server/structured_log.hpp"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <sstream>

namespace tessera::server {
namespace {

// Routes the default logger into a string for one test, in JSON or text format.
class CapturedLog {
 public:
  explicit CapturedLog(bool json) : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out_);
    auto logger = std::make_shared<spdlog::logger>("tesserad", sink);
    if (json)
      logger->set_formatter(std::make_unique<JsonLogFormatter>());
    else
      logger->set_pattern("%v");
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(logger);
  }
  ~CapturedLog() { spdlog::set_default_logger(previous_); }

  std::vector<std::string> lines() const {
    std::vector<std::string> result;
    std::istringstream in(out_.str());
    for (std::string line; std::getline(in, line);) result.push_back(line);
    return result;
  }

 private:
  std::shared_ptr<spdlog::logger> previous_;
  std::ostringstream out_;
};

TEST(JsonLog, AnEventIsOneObjectWithItsFields) {
  CapturedLog log(true);
  const std::string name =
      "q\"uote \\ new\nline\r tab\t nul-less \x01\x1f del\x7f bad\xff utf8 \xc3\xa9";
  log_event(spdlog::level::info, "job_submitted",
            {{"job_id", std::string("job-1")},
             {"name", name},
             {"tiles", std::uint64_t{80}},
             {"priority", std::int64_t{-3}},
             {"seconds", 1.5},
             {"resumed", false}},
            "job job-1 submitted");
  const auto lines = log.lines();
  ASSERT_EQ(lines.size(), 1u);  // the newline in the name did not split the line
  const nlohmann::json line = nlohmann::json::parse(lines[0]);
  EXPECT_EQ(line["level"], "info");
  EXPECT_EQ(line["logger"], "tesserad");
  EXPECT_EQ(line["event"], "job_submitted");
  EXPECT_EQ(line["message"], "job job-1 submitted");
  EXPECT_EQ(line["job_id"], "job-1");
  EXPECT_EQ(line["tiles"], 80);
  EXPECT_EQ(line["priority"], -3);
  EXPECT_EQ(line["seconds"], 1.5);
  EXPECT_EQ(line["resumed"], false);
  // Every byte survives but the one that is not UTF-8, which becomes U+FFFD.
  std::string expected = name;
  expected.replace(expected.find('\xff'), 1, "\xef\xbf\xbd");
  EXPECT_EQ(line["name"], expected);
  EXPECT_TRUE(line["time"].is_string());
}

TEST(JsonLog, PlainLinesHaveNoEventAndNoStaleFields) {
  CapturedLog log(true);
  log_event(spdlog::level::info, "rpc", {{"method", std::string("/x/Y")}}, "rpc line");
  spdlog::warn("plain {}", "line with \"quotes\"");
  const auto lines = log.lines();
  ASSERT_EQ(lines.size(), 2u);
  const nlohmann::json plain = nlohmann::json::parse(lines[1]);
  EXPECT_EQ(plain["level"], "warning");
  EXPECT_EQ(plain["message"], "plain line with \"quotes\"");
  EXPECT_FALSE(plain.contains("event"));
  EXPECT_FALSE(plain.contains("method"));
}

TEST(JsonLog, TextFormatLogsTheTextAloneAndLevelsFilterEvents) {
  CapturedLog log(false);
  log_event(spdlog::level::info, "rpc", {{"method", std::string("/x/Y")}}, "rpc /x/Y: OK");
  log_event(spdlog::level::debug, "rpc", {{"method", std::string("/grpc.health.v1.Health/Check")}},
            "not shown at info");
  EXPECT_EQ(log.lines(), std::vector<std::string>{"rpc /x/Y: OK"});
}

}  // namespace
}  // namespace tessera::server
