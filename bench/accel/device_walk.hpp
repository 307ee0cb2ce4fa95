#pragma once
#include <string>

namespace tessera::bench {

// The device layout's two walks of a mesh on this CPU, one scalar ray at a time as a GPU
// thread runs them: the binary BVH (traverse_bvh) and its compressed eight-wide form
// (traverse_compressed_wide), built as PreparedScene::device_source builds them. Prints the
// trees' sizes, triangle tests per ray and Mrays/s of each, and checks that both find the
// same hits. No GPU is needed; the figures say how much less memory a ray reads, not how
// fast a GPU runs.
int run_device_walk(const std::string& mesh_path, const std::string& rays_path, unsigned threads,
                    unsigned repeat);

}  // namespace tessera::bench
