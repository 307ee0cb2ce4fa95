#pragma once
#include <vector>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

// Renders the whole image on the calling thread, tile by tile: the reference the tests
// compare the daemon's and `tessera render --local`'s tiled output with, and the
// benchmarks' render. (The CLI and the daemon render tiles themselves, on their own threads.)
std::vector<float> render_image(const PreparedScene& scene);

}  // namespace tessera
