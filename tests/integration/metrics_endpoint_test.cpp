// The Prometheus endpoint of an in-process daemon, scraped over HTTP while a job renders:
// the counters move during the job and add up to the job's exact size after it; every
// line is valid exposition text; nothing but GET /metrics is served.
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include "client/client.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "server/daemon.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;

// Samples by their full name with labels: `tessera_jobs{state="running"}` -> 1.
std::map<std::string, double> scrape(int port) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(30, 0);
  const auto response = http.Get("/metrics");
  if (!response) throw std::runtime_error("scrape failed");
  EXPECT_EQ(response->status, 200);
  EXPECT_EQ(response->get_header_value("Content-Type").rfind("text/plain; version=0.0.4", 0), 0u);
  const std::regex sample_line(
      R"(^(tessera_[a-z_]+(\{[a-z_]+="[^"]*"(,[a-z_]+="[^"]*")*\})?) (\S+)$)");
  const std::regex comment_line(R"(^# (HELP|TYPE) tessera_[a-z_]+ .+$)");
  std::map<std::string, double> samples;
  std::istringstream lines(response->body);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch match;
    if (std::regex_match(line, match, sample_line))
      samples[match[1]] = std::stod(match[4]);
    else
      EXPECT_TRUE(std::regex_match(line, comment_line)) << "not exposition text: " << line;
  }
  return samples;
}

TEST(MetricsEndpoint, CountersMoveDuringAJobAndAddUpAfterIt) {
  server::DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.metrics_listen = "127.0.0.1:0";
  config.threads = 2;
  config.log_level = "warn";
  server::Daemon daemon(config);
  daemon.start();
  const int port = daemon.metrics_port();
  ASSERT_GT(port, 0);

  const auto idle = scrape(port);
  EXPECT_EQ(idle.at("tessera_rays_traced_total"), 0);
  EXPECT_EQ(idle.at("tessera_jobs{state=\"running\"}"), 0);
  EXPECT_EQ(idle.at("tessera_render_threads"), 2);

  // 64 tiles of 16x16 at 64 spp: seconds of work on two threads.
  const std::uint32_t width = 128, height = 128, spp = 64;
  Client client(ClientOptions{.target = daemon.address()});
  const v1::Job job =
      client.submit(make_submit_request(test::cornell(width, height, spp, 16), "metrics", 0));

  const auto wait_for_tiles = [&](std::uint32_t tiles) {
    const auto give_up = std::chrono::steady_clock::now() + 120s;
    while (client.get(job.id()).progress().tiles_done() < tiles &&
           std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(5ms);
  };
  wait_for_tiles(4);
  const auto early = scrape(port);
  wait_for_tiles(24);
  const auto later = scrape(port);
  const bool finished_early = client.get(job.id()).state() == v1::JOB_STATE_COMPLETED;
  EXPECT_GT(early.at("tessera_rays_traced_total"), 0);
  EXPECT_GT(early.at("tessera_tiles_rendered_total"), 0);
  EXPECT_GT(later.at("tessera_rays_traced_total"), early.at("tessera_rays_traced_total"));
  EXPECT_GT(later.at("tessera_tiles_rendered_total"), early.at("tessera_tiles_rendered_total"));
  EXPECT_GT(later.at("tessera_trace_seconds_total"), early.at("tessera_trace_seconds_total"));
  if (!finished_early) {
    EXPECT_EQ(later.at("tessera_jobs{state=\"running\"}"), 1);
  }
  EXPECT_EQ(early.at("tessera_scene_prepare_seconds_count"), 1);
  EXPECT_EQ(early.at("tessera_job_queue_seconds_count"), 1);

  client.stream_tiles(job.id(), [](const v1::Tile&) {});
  // The stream may end before the worker that stored the last tile has counted it.
  std::map<std::string, double> done;
  for (int i = 0; i < 500; ++i) {
    done = scrape(port);
    if (done.at("tessera_tiles_in_flight") == 0) break;
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_EQ(done.at("tessera_jobs{state=\"completed\"}"), 1);
  EXPECT_EQ(done.at("tessera_jobs{state=\"running\"}"), 0);
  EXPECT_EQ(done.at("tessera_job_run_seconds_count{state=\"completed\"}"), 1);
  EXPECT_EQ(done.at("tessera_job_run_seconds_bucket{state=\"completed\",le=\"+Inf\"}"), 1);
  EXPECT_EQ(done.at("tessera_tiles_rendered_total"), 64);
  double by_device = 0;  // the CPU's, and any GPU's where one renders
  for (const auto& [key, value] : done)
    if (key.starts_with("tessera_tiles_rendered_by_device_total{")) by_device += value;
  EXPECT_EQ(by_device, 64);
  EXPECT_TRUE(done.contains("tessera_tiles_rendered_by_device_total{device=\"cpu\"}"));
  EXPECT_EQ(done.at("tessera_samples_rendered_total"), double{width} * height * spp);
  EXPECT_EQ(done.at("tessera_rays_traced_total"),
            static_cast<double>(client.get(job.id()).progress().rays_traced()));
  EXPECT_EQ(done.at("tessera_queue_depth"), 0);
  EXPECT_EQ(done.at("tessera_tiles_in_flight"), 0);
  EXPECT_GT(done.at("tessera_process_resident_memory_bytes"), 1e6);
  daemon.shutdown();
}

TEST(MetricsEndpoint, ServesNothingButGetMetrics) {
  server::DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.metrics_listen = "127.0.0.1:0";
  config.threads = 1;
  config.log_level = "warn";
  server::Daemon daemon(config);
  daemon.start();
  httplib::Client http("127.0.0.1", daemon.metrics_port());
  EXPECT_EQ(http.Get("/")->status, 404);
  EXPECT_EQ(http.Get("/metrics/../debug")->status, 404);
  EXPECT_EQ(http.Post("/metrics", "x", "text/plain")->status, 404);
  EXPECT_EQ(http.Delete("/metrics")->status, 404);
  EXPECT_EQ(http.Get("/metrics")->status, 200);
}

TEST(MetricsEndpoint, OffByDefaultAndABusyPortFailsTheStart) {
  server::DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.threads = 1;
  config.log_level = "warn";
  server::Daemon first(config);
  first.start();
  EXPECT_EQ(first.metrics_port(), 0);

  config.metrics_listen = "127.0.0.1:0";
  server::Daemon with_metrics(config);
  with_metrics.start();
  config.metrics_listen = "127.0.0.1:" + std::to_string(with_metrics.metrics_port());
  server::Daemon clash(config);
  EXPECT_THROW(clash.start(), std::runtime_error);
}

}  // namespace
}  // namespace tessera
