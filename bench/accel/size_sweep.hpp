#pragma once
#include <cstdint>
#include <vector>

namespace tessera::bench {

// Throughput of every structure on random triangle soups of the given sizes, with rays
// from a sphere around the soup aimed at random points inside it; prints one table row per
// size. The figures behind choose_accel_kind's threshold.
void run_size_sweep(const std::vector<std::uint32_t>& sizes, std::uint32_t ray_count,
                    unsigned repeat);

}  // namespace tessera::bench
