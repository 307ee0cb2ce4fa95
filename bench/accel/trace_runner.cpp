#include "trace_runner.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <utility>
#include <vector>

namespace tessera::bench {

TraceTiming run_trace(std::size_t ray_count, unsigned threads, unsigned repeat,
                      const TraceChunk& trace, std::vector<float>* t_out) {
  std::vector<float> t(ray_count);
  tbb::task_arena arena(static_cast<int>(threads));
  TraceTiming timing;
  timing.best_seconds = 1e300;
  timing.best_cpu_seconds = 1e300;
  for (unsigned run = 0; run < std::max(1u, repeat); ++run) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ray_count, 256),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          trace(r.begin(), r.end(), t.data() + r.begin());
                        });
    });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    timing.best_seconds = std::min(timing.best_seconds, seconds);
    timing.best_cpu_seconds = std::min(
        timing.best_cpu_seconds, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
  }
  for (float value : t) {
    if (std::isinf(value)) continue;
    ++timing.hits;
    timing.tsum += value;
  }
  if (t_out != nullptr) *t_out = std::move(t);
  timing.mrays_per_s = static_cast<double>(ray_count) / timing.best_seconds * 1e-6;
  return timing;
}

void print_result_line(const TraceTiming& timing) {
  std::printf("mrays_per_s=%.3f hits=%llu tsum=%.6f\n", timing.mrays_per_s,
              static_cast<unsigned long long>(timing.hits), timing.tsum);
  std::fflush(stdout);
}

}  // namespace tessera::bench
