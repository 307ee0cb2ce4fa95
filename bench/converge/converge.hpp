#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::bench {

struct ConvergeOptions {
  std::string sampler;         // empty: the scene's render.sampler
  std::string light_strategy;  // empty: the scene's render.light_strategy
  bool light_tree = true;      // false: pick lights by power alone
  std::string scene;           // YAML scene file
  std::string reference;       // EXR to compare with; empty: render one
  std::uint32_t reference_spp = 4096;
  std::vector<std::uint32_t> spp{1, 2, 4, 8, 16, 32, 64, 128, 256};
  std::uint32_t width = 0;      // 0: the scene's
  std::uint32_t height = 0;     // 0: the scene's
  std::uint32_t max_depth = 0;  // 0: the scene's
  unsigned threads = 0;         // 0: every hardware thread
  double target = 1e-3;         // relMSE whose time is estimated
  std::string csv;              // write the series here
  std::string plot;             // write a log-log plot (PNG) here
  std::string save_reference;   // write the rendered reference here (EXR)
  // A second renderer measured the same way against its own reference ("cycles" or empty).
  std::string peer;
  std::string blender = "blender";  // the Blender executable the Cycles peer runs
  std::string peer_script;          // empty: bench/peers/cycles_render.py of this source tree
  std::string peer_dir;             // scene JSON, peer EXRs, Blender's log; empty: beside --csv
  std::string export_json;          // write the scene as the peer reads it, then stop
  // Also measure Tessera with adaptive sampling (render.target_error) at each of these
  // targets, each pixel capped at adaptive_max_spp; empty: not measured.
  std::vector<double> adaptive_targets;
  std::uint32_t adaptive_max_spp = 0;  // 0: 4 x the largest of `spp`
  // Also measure Tessera denoised (the à-trous filter on albedo, normal and variance AOVs),
  // at each of `spp`, the filter's time included.
  bool denoise = false;
  // Where the series render: "cpu" (`threads` threads) or "gpu" (CUDA device 0, the whole
  // image as one tile; builds with the GPU backend only). The reference renders on the CPU.
  std::string device = "cpu";
};

// Renders the scene at each spp (wall time of the render alone, scene preparation
// excluded), measures RMSE and relMSE against the reference, prints a table and the time
// to `target` relMSE. Returns the process exit code.
int run_converge(const ConvergeOptions& options);

}  // namespace tessera::bench
