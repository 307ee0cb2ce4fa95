// DaemonMetrics: the per-device tile counters and their exposition (the scheduler's counts
// are tested in scheduler_test.cpp, the endpoint in tests/integration).
#include "server/metrics.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tessera::server {
namespace {

TEST(DaemonMetrics, TilesAreCountedByTheWorkerThatRenderedThem) {
  DaemonMetrics metrics;
  metrics.name_tile_workers({"cpu", "gpu0 \"A\" \\ B"});
  metrics.tile_rendered_by(0);
  metrics.tile_rendered_by(1);
  metrics.tile_rendered_by(1);
  metrics.tile_fell_back(0);
  metrics.tile_rendered_by(kMaxTileWorkers);  // beyond the counters: ignored, not a crash
  EXPECT_EQ(metrics.tiles_rendered_by(0), 1u);
  EXPECT_EQ(metrics.tiles_rendered_by(1), 2u);
  EXPECT_EQ(metrics.tiles_fallen_back(0), 1u);
  const std::string text = metrics.exposition({});
  EXPECT_NE(text.find("tessera_tiles_rendered_by_device_total{device=\"cpu\"} 1\n"),
            std::string::npos)
      << text;
  // The driver's name, quotes and backslashes escaped as the text format requires.
  EXPECT_NE(
      text.find("tessera_tiles_rendered_by_device_total{device=\"gpu0 \\\"A\\\" \\\\ B\"} 2\n"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("tessera_device_fallbacks_total{device=\"gpu0 \\\"A\\\" \\\\ B\"} 1\n"),
            std::string::npos)
      << text;
}

TEST(DaemonMetrics, WithTheCpuAloneThereAreNoFallbackLines) {
  DaemonMetrics metrics;
  EXPECT_EQ(metrics.exposition({}).find("by_device"), std::string::npos) << "nothing named yet";
  metrics.name_tile_workers({"cpu"});
  const std::string text = metrics.exposition({});
  EXPECT_NE(text.find("tessera_tiles_rendered_by_device_total{device=\"cpu\"} 0\n"),
            std::string::npos);
  EXPECT_EQ(text.find("tessera_device_fallbacks_total"), std::string::npos);
}

}  // namespace
}  // namespace tessera::server
