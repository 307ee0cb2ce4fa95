#pragma once
#include <cstdint>

#include "tessera/math/host_device.hpp"
#include "tessera/math/sobol.hpp"

namespace tessera {

// One pixel's Sobol seeds, kept while its samples run: the pixel key and each pair's
// SobolPairSeeds depend on the job's seed, the pixel and the pair, not on the sample index,
// yet a sample stream formed them for every sample (five hashes a pair, four for the key;
// about a third of the Sobol sampler's instructions). A tile's loop keeps one memo and
// hands it to each sample's stream (SampleStream's last argument); the stream fills a
// pair's seeds the first time the pixel uses the pair and reads them after that. The
// values are the same with or without it. Not shared between threads.
class SobolSeedMemo {
 public:
  // Pairs past this (depths past 20, the lens' far dimensions) are hashed as before.
  static constexpr std::uint32_t kPairs = 64;

  // The key of pixel (x, y) under `seed` (sobol_pixel_key). Another pixel than the last
  // empties the memo.
  TESSERA_HD std::uint32_t pixel_key(std::uint64_t seed, std::uint32_t x, std::uint32_t y) {
    if (!has_pixel_ || x != x_ || y != y_ || seed != seed_) {
      key_ = sobol_pixel_key(seed, x, y);
      seed_ = seed;
      x_ = x;
      y_ = y;
      filled_ = 0;
      has_pixel_ = true;
    }
    return key_;
  }

  // Pair `pair`'s seeds (pair < kPairs) for the pixel pixel_key was last asked for.
  TESSERA_HD TESSERA_FORCE_INLINE const SobolPairSeeds& seeds(std::uint32_t pair) {
    if (((filled_ >> pair) & 1U) == 0) [[unlikely]]
      fill(pair);
    return seeds_[pair];
  }

 private:
  // Out of line: a pixel's first sample takes it, its later samples only test the bit.
#if !defined(__CUDA_ARCH__) && (defined(__GNUC__) || defined(__clang__))
  __attribute__((noinline, cold))
#endif
  TESSERA_HD void
  fill(std::uint32_t pair) {
    seeds_[pair] = sobol_pair_seeds(key_, pair);
    filled_ |= std::uint64_t{1} << pair;
  }

  std::uint64_t seed_ = 0;
  std::uint32_t x_ = 0, y_ = 0;
  std::uint32_t key_ = 0;
  std::uint64_t filled_ = 0;  // bit p: seeds_[p] holds pair p's seeds
  bool has_pixel_ = false;
  SobolPairSeeds seeds_[kPairs];
};

}  // namespace tessera
