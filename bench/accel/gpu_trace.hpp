#pragma once
#include <string>

namespace tessera::bench {

// Closest hits of a ray file on a CUDA device (gpu::MeshRayTracer), with the compressed and
// the binary walk, against the CPU's triangle structure on `threads` threads of this
// machine: Mrays/s of each, and the rays on which the GPU and the CPU disagree. Built only
// with the GPU backend (TESSERA_HAS_CUDA).
int run_gpu_trace(const std::string& mesh_path, const std::string& rays_path, unsigned threads,
                  unsigned repeat, int device);

}  // namespace tessera::bench
