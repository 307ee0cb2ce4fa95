#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace tessera::bench {

// Traces rays [begin, end) and writes each ray's hit distance to t_out[i - begin]
// (+infinity on a miss; for occlusion queries 1 when blocked).
using TraceChunk = std::function<void(std::size_t begin, std::size_t end, float* t_out)>;

struct TraceTiming {
  double best_seconds = 0.0;  // fastest of the repeats, wall clock
  double best_cpu_seconds =
      0.0;  // least process CPU time of the repeats: steadier on a busy machine
  double mrays_per_s = 0.0;
  std::uint64_t hits = 0;
  double tsum =
      0.0;  // sum of t over hits, added in ray order so it is the same on any thread count
};

// Runs `trace` over all rays `repeat` times on `threads` TBB workers (chunks of 256 rays,
// handed out dynamically) and keeps the fastest run.
// Per-ray results of the last run go to `t_out` when given.
TraceTiming run_trace(std::size_t ray_count, unsigned threads, unsigned repeat,
                      const TraceChunk& trace, std::vector<float>* t_out = nullptr);

// The line both tools print last.
void print_result_line(const TraceTiming& timing);

}  // namespace tessera::bench
