#include "client/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tessera {

namespace {

std::string printf_string(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, a, b, c);
  return buffer;
}

}  // namespace

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) seconds = 0.0;
  if (seconds < 10.0) return printf_string("%.2f s", seconds);
  if (seconds < 60.0) return printf_string("%.1f s", seconds);
  const auto total = static_cast<long long>(std::llround(seconds));
  char buffer[48];
  if (total < 3600)
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld", total / 60, total % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60,
                  total % 60);
  return buffer;
}

std::string format_rate(double rays_per_second) {
  if (!std::isfinite(rays_per_second) || rays_per_second < 0.0) rays_per_second = 0.0;
  if (rays_per_second < 1e3) return printf_string("%.0f rays/s", rays_per_second);
  if (rays_per_second < 1e6) return printf_string("%.1f krays/s", rays_per_second / 1e3);
  if (rays_per_second < 1e9) return printf_string("%.2f Mrays/s", rays_per_second / 1e6);
  return printf_string("%.2f Grays/s", rays_per_second / 1e9);
}

int percent_done(const ProgressSnapshot& progress) {
  if (progress.tiles_total == 0) return 0;
  const std::uint64_t done = std::min(progress.tiles_done, progress.tiles_total);
  return static_cast<int>(done * 100 / progress.tiles_total);
}

namespace {

// " tiles", or with passes " tile passes  pass 2/4".
std::string units_text(const ProgressSnapshot& progress) {
  if (progress.passes <= 1) return " tiles";
  const std::uint32_t current = std::min(progress.passes_done + 1, progress.passes);
  return " tile passes  pass " + std::to_string(current) + "/" + std::to_string(progress.passes);
}

std::string eta_text(const ProgressSnapshot& progress) {
  if (progress.tiles_total > 0 && progress.tiles_done >= progress.tiles_total) return "done";
  if (progress.eta_seconds <= 0.0 || !std::isfinite(progress.eta_seconds)) return "ETA --";
  return "ETA " + format_duration(progress.eta_seconds);
}

}  // namespace

std::string format_progress_bar(const ProgressSnapshot& progress, int bar_width) {
  bar_width = std::max(bar_width, 1);
  const int filled =
      progress.tiles_total == 0
          ? 0
          : static_cast<int>(
                static_cast<std::uint64_t>(std::min(progress.tiles_done, progress.tiles_total)) *
                static_cast<std::uint64_t>(bar_width) / progress.tiles_total);
  std::string line(1, '[');
  line.append(static_cast<std::size_t>(filled), '#');
  line.append(static_cast<std::size_t>(bar_width - filled), '.');
  line.append("] ");
  const std::string total = std::to_string(progress.tiles_total);
  std::string done = std::to_string(progress.tiles_done);
  if (done.size() < total.size()) done.insert(0, total.size() - done.size(), ' ');
  char percent[8];
  std::snprintf(percent, sizeof percent, "%3d%%", percent_done(progress));
  line += done + "/" + total + units_text(progress) + "  " + percent + "  " +
          format_rate(progress.rays_per_second) + "  " + eta_text(progress);
  return line;
}

std::string format_progress_line(const ProgressSnapshot& progress) {
  return std::to_string(percent_done(progress)) + "% (" + std::to_string(progress.tiles_done) +
         "/" + std::to_string(progress.tiles_total) + units_text(progress) + "), " +
         format_rate(progress.rays_per_second) + ", " + eta_text(progress);
}

ProgressReporter::ProgressReporter(std::ostream& out, bool interactive)
    : out_(out), interactive_(interactive) {}

void ProgressReporter::update(const ProgressSnapshot& progress) {
  const bool last = progress.tiles_total > 0 && progress.tiles_done >= progress.tiles_total;
  if (interactive_) {
    const auto now = std::chrono::steady_clock::now();
    if (!last && line_open_ && now - last_draw_ < std::chrono::milliseconds(50)) return;
    last_draw_ = now;
    std::string line = format_progress_bar(progress);
    // Pad over the previous, possibly longer, line rather than relying on terminal escapes.
    const std::size_t width = line.size();
    if (width < last_width_) line.append(last_width_ - width, ' ');
    last_width_ = width;
    out_ << '\r' << line << std::flush;
    line_open_ = true;
    return;
  }
  const int decile = percent_done(progress) / 10;
  if (decile <= last_decile_) return;
  last_decile_ = decile;
  out_ << "tessera: " << format_progress_line(progress) << '\n' << std::flush;
}

void ProgressReporter::finish() {
  if (line_open_) out_ << '\n' << std::flush;
  line_open_ = false;
}

bool stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

}  // namespace tessera
