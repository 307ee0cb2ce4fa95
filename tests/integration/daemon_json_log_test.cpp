// tesserad --log-format json: every line of the log is one JSON object with time, level and
// message; RPCs log one line each with method, peer, status code and duration; a job's
// "submitted" comes before its "started"; a name full of quotes, newlines and control
// characters stays inside its string.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "client/client_error.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "tesserad_process.hpp"

namespace tessera {
namespace {

using test::cornell;
using test::TesseradProcess;

class DaemonJsonLogTest : public test::TesseradDirTest {};

std::vector<nlohmann::json> parse_every_line(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line;
  std::vector<nlohmann::json> lines;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    try {
      lines.push_back(nlohmann::json::parse(line));
    } catch (const nlohmann::json::parse_error& e) {
      ADD_FAILURE() << "line " << number << " is not JSON (" << e.what() << "): " << line;
    }
  }
  return lines;
}

// The index of the first line with `event` and, when given, `job_id`; -1 when none.
long find_event(const std::vector<nlohmann::json>& lines, const std::string& event,
                const std::string& job_id = {}) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].value("event", "") == event &&
        (job_id.empty() || lines[i].value("job_id", "") == job_id))
      return static_cast<long>(i);
  return -1;
}

TEST_F(DaemonJsonLogTest, EveryLineParsesAndCarriesItsFields) {
  const std::string name = "quote\" backslash\\ newline\n tab\t bell\x07 escape\x1b[31m end";
  std::string job_id;
  {
    TesseradProcess daemon(data(), log(), 2, "127.0.0.1:0", {"--log-format", "json"});
    Client client(ClientOptions{.target = daemon.address()});
    const v1::Job job = client.submit(make_submit_request(cornell(32, 32, 2, 16), name, 0));
    job_id = job.id();
    client.stream_tiles(job_id, [](const v1::Tile&) {});
    EXPECT_THROW(client.get("no-such-job"), ClientError);
    EXPECT_EQ(daemon.terminate(), 0);
  }

  const std::vector<nlohmann::json> lines = parse_every_line(log());
  ASSERT_GE(lines.size(), 5u);
  const std::regex iso_time(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)");
  for (const nlohmann::json& line : lines) {
    ASSERT_TRUE(line.is_object()) << line.dump();
    ASSERT_TRUE(line.contains("time") && line["time"].is_string()) << line.dump();
    EXPECT_TRUE(std::regex_match(line["time"].get<std::string>(), iso_time)) << line.dump();
    ASSERT_TRUE(line.contains("level") && line["level"].is_string()) << line.dump();
    ASSERT_TRUE(line.contains("message") && line["message"].is_string()) << line.dump();
  }

  const long submitted = find_event(lines, "job_submitted", job_id);
  const long started = find_event(lines, "job_started", job_id);
  const long completed = find_event(lines, "job_completed", job_id);
  ASSERT_GE(submitted, 0);
  ASSERT_GE(started, 0);
  ASSERT_GE(completed, 0);
  EXPECT_LT(submitted, started) << "started logged before submitted";
  EXPECT_LT(started, completed);
  EXPECT_EQ(lines[submitted]["name"], name);  // the exact name, escaped only by JSON
  EXPECT_EQ(lines[submitted]["tiles"], 4);
  EXPECT_GT(lines[completed]["rays"].get<std::uint64_t>(), 0u);
  // Where the tiles went: the CPU threads first, then each GPU the daemon renders on.
  const std::string split = lines[completed]["tiles_rendered_by"].get<std::string>();
  EXPECT_EQ(split.rfind("cpu ", 0), 0u) << split;
  if (split.find(',') == std::string::npos) {
    EXPECT_EQ(split, "cpu 4");  // no GPU
  }

  bool submit_rpc = false;
  bool not_found_rpc = false;
  for (const nlohmann::json& line : lines) {
    if (line.value("event", "") != "rpc") continue;
    ASSERT_TRUE(line["duration_ms"].is_number()) << line.dump();
    EXPECT_GE(line["duration_ms"].get<double>(), 0.0);
    EXPECT_EQ(line["peer"].get<std::string>().rfind("ipv4:127.0.0.1:", 0), 0u) << line.dump();
    if (line["method"] == "/tessera.v1.RenderService/SubmitJob" && line["code"] == "OK")
      submit_rpc = true;
    if (line["method"] == "/tessera.v1.RenderService/GetJob" && line["code"] == "NOT_FOUND") {
      not_found_rpc = true;
      EXPECT_NE(line["error"].get<std::string>().find("no-such-job"), std::string::npos);
    }
  }
  EXPECT_TRUE(submit_rpc);
  EXPECT_TRUE(not_found_rpc);
}

}  // namespace
}  // namespace tessera
