#include <gtest/gtest.h>

#include <sstream>

#include "client/progress.hpp"

namespace tessera {
namespace {

TEST(Progress, DurationsPickAReadableUnit) {
  EXPECT_EQ(format_duration(0.0), "0.00 s");
  EXPECT_EQ(format_duration(0.424), "0.42 s");
  EXPECT_EQ(format_duration(12.34), "12.3 s");
  EXPECT_EQ(format_duration(245.0), "4:05");
  EXPECT_EQ(format_duration(3723.0), "1:02:03");
  EXPECT_EQ(format_duration(-1.0), "0.00 s");
}

TEST(Progress, RatesPickAReadableUnit) {
  EXPECT_EQ(format_rate(950.0), "950 rays/s");
  EXPECT_EQ(format_rate(12345.0), "12.3 krays/s");
  EXPECT_EQ(format_rate(3.214e6), "3.21 Mrays/s");
  EXPECT_EQ(format_rate(1.05e9), "1.05 Grays/s");
}

TEST(Progress, PercentRoundsDownSoHundredMeansDone) {
  EXPECT_EQ(percent_done({79, 80}), 98);
  EXPECT_EQ(percent_done({80, 80}), 100);
  EXPECT_EQ(percent_done({1, 3}), 33);
  EXPECT_EQ(percent_done({0, 0}), 0);
}

TEST(Progress, BarShowsTilesPercentRateAndEta) {
  ProgressSnapshot p{40, 80, 0, 2.0, 3.214e6, 4.0};
  EXPECT_EQ(format_progress_bar(p, 10), "[#####.....] 40/80 tiles   50%  3.21 Mrays/s  ETA 4.00 s");
  p.tiles_done = 80;
  EXPECT_EQ(format_progress_bar(p, 10), "[##########] 80/80 tiles  100%  3.21 Mrays/s  done");
  p = {3, 120, 0, 0.0, 0.0, 0.0};
  EXPECT_EQ(format_progress_bar(p, 4), "[....]   3/120 tiles    2%  0 rays/s  ETA --");
}

TEST(Progress, PassesShowWhichPassTheImageIsIn) {
  ProgressSnapshot p{40, 80, 0, 2.0, 3.214e6, 4.0, 4, 1};
  EXPECT_EQ(format_progress_bar(p, 10),
            "[#####.....] 40/80 tile passes  pass 2/4   50%  3.21 Mrays/s  ETA 4.00 s");
  EXPECT_EQ(format_progress_line(p), "50% (40/80 tile passes  pass 2/4), 3.21 Mrays/s, ETA 4.00 s");
  p.tiles_done = 80;
  p.passes_done = 4;
  EXPECT_EQ(format_progress_bar(p, 10),
            "[##########] 80/80 tile passes  pass 4/4  100%  3.21 Mrays/s  done");
}

TEST(Progress, PlainOutputPrintsOneLinePerTenPercent) {
  std::ostringstream out;
  ProgressReporter reporter(out, /*interactive=*/false);
  for (std::uint32_t done = 1; done <= 80; ++done) reporter.update({done, 80, 0, 1.0, 1e6, 1.0});
  reporter.finish();
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 10);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_NE(text.find("tessera: 10% (8/80 tiles)"), std::string::npos) << text;
  EXPECT_NE(text.find("tessera: 100% (80/80 tiles), 1.00 Mrays/s, done\n"), std::string::npos)
      << text;
}

TEST(Progress, PlainOutputSkipsStepsWhenTilesArriveInBursts) {
  std::ostringstream out;
  ProgressReporter reporter(out, false);
  reporter.update({1, 4, 0, 0, 0, 0});  // 25%
  reporter.update({4, 4, 0, 0, 0, 0});  // 100%
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
}

TEST(Progress, TerminalOutputRedrawsOneLineAndEndsItOnFinish) {
  std::ostringstream out;
  ProgressReporter reporter(out, /*interactive=*/true);
  for (std::uint32_t done = 1; done <= 5; ++done) reporter.update({done, 5, 0, 1.0, 2e6, 0.5});
  EXPECT_EQ(out.str().find('\n'), std::string::npos);
  reporter.finish();
  const std::string text = out.str();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
  // The last tile is always drawn, whatever the redraw throttling skipped.
  const std::string last_line = text.substr(text.rfind('\r') + 1);
  EXPECT_NE(last_line.find("5/5 tiles  100%"), std::string::npos) << last_line;
}

}  // namespace
}  // namespace tessera
