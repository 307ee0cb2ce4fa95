#pragma once
#include <cstdint>

#include "tessera/math/hash.hpp"
#include "tessera/math/host_device.hpp"
#include "tessera/math/sampler_kind.hpp"
#include "tessera/math/sobol.hpp"
#include "tessera/math/sobol_seed_memo.hpp"

namespace tessera {

// Counter-based random numbers: every value is a pure function of (job seed, pixel,
// sample index, dimension), so an image does not depend on thread count, tile size or
// the order tiles are rendered in. The kind is a runtime value so one compiled pipeline
// serves both samplers; the branch is uniform across a tile.
class SampleStream {
 public:
  // Four arguments: the independent sampler, whose values are those this class gave before
  // it had kinds. With Sobol, `memo` (null: none) keeps the pixel's seeds across its samples
  // (SobolSeedMemo): the values are the same, with fewer hashes; the stream must not outlive
  // it, and one memo serves one thread.
  TESSERA_HD SampleStream(std::uint64_t seed, std::uint32_t pixel_x, std::uint32_t pixel_y,
                          std::uint32_t sample_index, SamplerKind kind = SamplerKind::kIndependent,
                          SobolSeedMemo* memo = nullptr) {
    restart(seed, pixel_x, pixel_y, sample_index, kind, memo);
  }

  // The stream of another sample, in place: the same as assigning SampleStream(...), without
  // the temporary. Its copy into a path's payload read the temporary's fields back as
  // 16-byte loads straight after they were stored one by one, which the processor cannot
  // forward from its store buffer: 1.5% of a path-traced sample's time on the converge scene
  // two_lights (perf, Zen 5), at Pipeline::launch's init_payload.
  TESSERA_HD TESSERA_FORCE_INLINE void restart(std::uint64_t seed, std::uint32_t pixel_x,
                                               std::uint32_t pixel_y, std::uint32_t sample_index,
                                               SamplerKind kind = SamplerKind::kIndependent,
                                               SobolSeedMemo* memo = nullptr) {
    kind_ = kind;
    index_ = sample_index;
    dimension_ = 0;
    kept_pair_ = ~0U;
    kept_index_ = 0;
    memo_ = nullptr;
    mirrored_index_ = 0;
    if (kind == SamplerKind::kSobol) {
      memo_ = memo;
      key_ = memo != nullptr ? memo->pixel_key(seed, pixel_x, pixel_y)
                             : sobol_pixel_key(seed, pixel_x, pixel_y);
      mirrored_index_ = reverse_bits(sample_index);
      return;
    }
    std::uint32_t h = mix32(static_cast<std::uint32_t>(seed) ^ 0x2545f491U);
    h = hash_combine(h, static_cast<std::uint32_t>(seed >> 32));
    h = hash_combine(h, pixel_x);
    h = hash_combine(h, pixel_y);
    h = hash_combine(h, sample_index);
    key_ = h;
  }

  // The next dimension's value in [0, 1). For Sobol, two consecutive calls starting at an
  // even dimension read the same 2D set; next_2d does that with one shuffle instead of two.
  TESSERA_HD float next() {
    const std::uint32_t d = dimension_++;
    if (kind_ == SamplerKind::kSobol) {
      std::uint32_t x = 0;
      std::uint32_t y = 0;
      const SobolPairSeeds seeds = pair_seeds(d >> 1);
      sobol_pair_from_index_mirrored(sobol_shuffled_index(seeds.shuffle, mirrored_index_), seeds.x,
                                     seeds.y, x, y);
      return unit_float_from_mirrored((d & 1U) != 0 ? y : x);
    }
    return uint_to_unit_float(hash_combine(key_, d));
  }

  // Two values from one 2D set (a pixel position, a direction, a point on a light), so
  // they are stratified jointly, not just each on its own. Starts at the next even
  // dimension, skipping one if the count is odd, for either kind so that both give a
  // bounce the same dimension numbers.
  TESSERA_HD TESSERA_FORCE_INLINE void next_2d(float& a, float& b) {
    dimension_ += dimension_ & 1U;
    if (kind_ == SamplerKind::kSobol) {
      const SobolPairSeeds seeds = pair_seeds(dimension_ >> 1);
      return take_pair(sobol_shuffled_index(seeds.shuffle, mirrored_index_), seeds, a, b);
    }
    a = next();
    b = next();
  }

  // As next_2d, and for Sobol keeps the pair's shuffled index, so that the pair joined to it
  // later (next_2d_joined) starts from it instead of forming it again: the pairs that lead
  // to a vertex (the camera's position in the pixel, a BSDF direction) draw with this.
  TESSERA_HD TESSERA_FORCE_INLINE void next_2d_kept(float& a, float& b) {
    dimension_ += dimension_ & 1U;
    if (kind_ != SamplerKind::kSobol) return next_2d(a, b);
    kept_pair_ = dimension_ >> 1;
    const SobolPairSeeds seeds = pair_seeds(kept_pair_);
    kept_index_ = sobol_shuffled_index(seeds.shuffle, mirrored_index_);
    take_pair(kept_index_, seeds, a, b);
  }

  // The next pair (as next_2d) joined to the pair that starts at even dimension `partner`:
  // for Sobol, dimensions 2 and 3 of the 4D set whose first two are that pair, so the two
  // are stratified jointly (sobol_joined_from_index_mirrored). A pair has at most one pair
  // joined to it. The partner's shuffled index is reused when next_2d_kept drew it last (one
  // permutation and one mirror fewer on the light sample's chain), and its seeds come from
  // the memo where there is one; the values are the same either way. The independent
  // sampler draws it as next_2d does.
  TESSERA_HD TESSERA_FORCE_INLINE void next_2d_joined(std::uint32_t partner, float& a, float& b) {
    if (kind_ != SamplerKind::kSobol) return next_2d(a, b);
    dimension_ += dimension_ & 1U;
    const std::uint32_t partner_pair = partner >> 1;
    const SobolPairSeeds seeds = pair_seeds(partner_pair);
    const std::uint32_t index = kept_pair_ == partner_pair
                                    ? kept_index_
                                    : sobol_shuffled_index(seeds.shuffle, mirrored_index_);
    std::uint32_t x = 0;
    std::uint32_t y = 0;
    sobol_joined_from_index_mirrored(index, seeds.joined_x, seeds.joined_y, x, y);
    take_mirrored(x, y, a, b);
  }

  // White noise for dimension `dimension`, whatever the kind: for decisions stratification
  // does not help (Russian roulette), at the cost of one hash.
  TESSERA_HD float white(std::uint32_t dimension) const {
    return uint_to_unit_float(hash_combine(hash_combine(key_, index_), dimension ^ 0x5bd1e995U));
  }

  // Jumps to a fixed dimension, so each bounce can own a block of dimensions whatever the
  // previous bounces consumed (a rejected or skipped sample then shifts nothing after it).
  TESSERA_HD void set_dimension(std::uint32_t dimension) { dimension_ = dimension; }
  TESSERA_HD std::uint32_t dimension() const { return dimension_; }
  TESSERA_HD SamplerKind kind() const { return kind_; }

 private:
  // A Sobol pair's two binary fractions, given with their bits mirrored, as the values of the
  // pair's two dimensions.
  TESSERA_HD void take_mirrored(std::uint32_t mx, std::uint32_t my, float& a, float& b) {
    dimension_ += 2;
    a = unit_float_from_mirrored(mx);
    b = unit_float_from_mirrored(my);
  }
  // The Sobol pair with this shuffled index and seeds (sobol_pair_from_index_mirrored), taken
  // as above.
  TESSERA_HD void take_pair(std::uint32_t index, const SobolPairSeeds& seeds, float& a, float& b) {
    std::uint32_t x = 0;
    std::uint32_t y = 0;
    sobol_pair_from_index_mirrored(index, seeds.x, seeds.y, x, y);
    take_mirrored(x, y, a, b);
  }
  // Sobol: pair `pair`'s seeds, from the memo where there is one and it holds that many pairs.
  TESSERA_HD TESSERA_FORCE_INLINE SobolPairSeeds pair_seeds(std::uint32_t pair) const {
    if (memo_ != nullptr && pair < SobolSeedMemo::kPairs) return memo_->seeds(pair);
    return sobol_pair_seeds(key_, pair);
  }

  std::uint32_t key_ = 0;    // independent: hash of seed, pixel, sample; Sobol: of seed, pixel
  std::uint32_t index_ = 0;  // the sample index
  std::uint32_t mirrored_index_ = 0;  // Sobol: its bits mirrored, formed once for every pair
  std::uint32_t dimension_ = 0;
  SobolSeedMemo* memo_ = nullptr;  // Sobol: the pixel's seeds, if the caller keeps them
  // Sobol: the pair next_2d_kept drew last (none: ~0) and its shuffled index.
  std::uint32_t kept_pair_ = ~0U;
  std::uint32_t kept_index_ = 0;
  SamplerKind kind_ = SamplerKind::kIndependent;
};

}  // namespace tessera
