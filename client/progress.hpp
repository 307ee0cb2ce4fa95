#pragma once
#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace tessera {

// Where a render stands, as the server reports it in each tile (or as --local measures it).
struct ProgressSnapshot {
  std::uint32_t tiles_done = 0;
  std::uint32_t tiles_total = 0;
  std::uint64_t rays = 0;
  double elapsed_seconds = 0.0;
  double rays_per_second = 0.0;
  double eta_seconds = 0.0;  // 0: unknown or done
  // A job with progressive passes: tiles_done and tiles_total count tile passes, and the
  // line also says which pass the image is in (passes_done + 1, or the last when done).
  std::uint32_t passes = 1;
  std::uint32_t passes_done = 0;
};

// "0.42 s", "12.3 s", "4:05", "1:02:03"
std::string format_duration(double seconds);
// "950 rays/s", "12.3 krays/s", "3.21 Mrays/s", "1.05 Grays/s"
std::string format_rate(double rays_per_second);
// Whole percent of tiles done, rounded down so 100 means every tile.
int percent_done(const ProgressSnapshot& progress);
// "[##########..........]  40/80 tiles  50%  3.21 Mrays/s  ETA 4.0 s" (with passes:
// "... 40/80 tile passes  pass 2/4  50% ...")
std::string format_progress_bar(const ProgressSnapshot& progress, int bar_width = 24);
// "50% (40/80 tiles), 3.21 Mrays/s, ETA 4.0 s"
std::string format_progress_line(const ProgressSnapshot& progress);

// Shows render progress: on a terminal, one line redrawn in place (at most ~20 times a
// second, always at the end); otherwise, e.g. into a log file, one plain line each time
// another 10% of the tiles is done.
class ProgressReporter {
 public:
  ProgressReporter(std::ostream& out, bool interactive);
  void update(const ProgressSnapshot& progress);
  // Ends the in-place line so later output starts on a fresh line.
  void finish();

 private:
  std::ostream& out_;
  bool interactive_;
  bool line_open_ = false;
  int last_decile_ = 0;
  std::chrono::steady_clock::time_point last_draw_{};
  std::size_t last_width_ = 0;
};

bool stderr_is_terminal();

}  // namespace tessera
