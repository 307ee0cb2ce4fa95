#pragma once
#include <cstdint>
#include <type_traits>

#include "tessera/math/hash.hpp"
#include "tessera/math/host_device.hpp"

namespace tessera {

// Owen-scrambled Sobol points as Burley describes them ("Practical Hash-based Owen
// Scrambling", JCGT 9(4), 2020), written from the paper's description:
//
// - Dimensions come in pairs (0, 1), (2, 3), ...; each pair is the 2D Sobol sequence, which
//   is a (0, 2)-sequence in base 2: every aligned block of 2^m points is a (0, m, 2)-net.
//   Higher Sobol dimensions have weaker 2D projections, so rather than use them, every pair
//   gets its own index shuffle and scramble (the paper's padding), which also decorrelates
//   the pairs from each other.
// - The sample index is shuffled per pixel and pair by a nested uniform scramble of its
//   bits. Bit k of the result depends only on the index's bits k and above, so the first
//   2^m indices map onto one aligned block of 2^m Sobol indices: every power-of-two prefix
//   of a pixel's samples is still a (0, m, 2)-net, in an order that differs per pixel.
// - Each coordinate is then Owen-scrambled by a hash (nested_uniform_scramble), which keeps
//   the net property and turns the error of smooth integrands into the fast-falling
//   variance of scrambled nets.
//
// Everything is a pure function of (seed, pixel, sample index, dimension): no tables, no
// state, the same on the CPU and the GPU.

// Forced inline (GCC kept it out of line) and a byte swap for the first two steps: render
// instructions -0.9% on the colour-bleed box, -0.7% on glossy_glass, the same pixels.
TESSERA_HD TESSERA_FORCE_INLINE constexpr std::uint32_t reverse_bits(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  if (!std::is_constant_evaluated()) return __brev(x);
#endif
#if !defined(__CUDA_ARCH__) && (defined(__GNUC__) || defined(__clang__))
  x = __builtin_bswap32(x);
#else
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
#endif
  x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
  x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
  x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
  return x;
}

// Partial mirrors for the values that keep only some of their bits: on the host by a table
// of mirrored bytes (two or three look-ups where reverse_bits is sixteen shifts, masks and
// ors; the mirrors were a twentieth of a render's instructions), on the device by __brev.
#if !defined(__CUDA_ARCH__)
struct MirroredBytes {
  std::uint8_t of[256];
};
constexpr MirroredBytes make_mirrored_bytes() {
  MirroredBytes t{};
  for (std::uint32_t byte = 0; byte < 256; ++byte)
    t.of[byte] = static_cast<std::uint8_t>(reverse_bits(byte) >> 24);
  return t;
}
inline constexpr MirroredBytes kMirroredBytes = make_mirrored_bytes();
#endif

// reverse_bits(x) & 0xffff: x's high 16 bits mirrored.
TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t reverse_high_16_bits(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  return __brev(x) & 0xffffU;
#else
  return static_cast<std::uint32_t>(kMirroredBytes.of[x >> 24]) |
         (static_cast<std::uint32_t>(kMirroredBytes.of[(x >> 16) & 0xffU]) << 8);
#endif
}

// reverse_bits(x) >> 8: x's low 24 bits mirrored, the 24 bits a float in [0, 1) keeps of a
// binary fraction (uint_to_unit_float).
TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t reverse_low_24_bits(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  return __brev(x) >> 8;
#else
  return (static_cast<std::uint32_t>(kMirroredBytes.of[x & 0xffU]) << 16) |
         (static_cast<std::uint32_t>(kMirroredBytes.of[(x >> 8) & 0xffU]) << 8) |
         static_cast<std::uint32_t>(kMirroredBytes.of[(x >> 16) & 0xffU]);
#endif
}

// A binary fraction's value in [0, 1) from the mirror of its bits (as the scrambles below
// produce it): uint_to_unit_float(reverse_bits(mirrored)), the same float.
TESSERA_HD TESSERA_FORCE_INLINE float unit_float_from_mirrored(std::uint32_t mirrored) {
  return static_cast<float>(reverse_low_24_bits(mirrored)) * (1.0f / 16777216.0f);
}

// Column `bit` of the generator matrix of Sobol dimension 0 or 1, as a 32-bit binary
// fraction (the most significant bit is 1/2): a point is the XOR of the columns of the
// index's set bits. Dimension 0 is the identity (van der Corput: the index's bits
// mirrored). Dimension 1 comes from the primitive polynomial x + 1 with m_1 = 1; its
// recurrence m_k = 2 m_{k-1} xor m_{k-1} makes each column the previous one xor itself
// shifted right by one (Pascal's triangle mod 2).
TESSERA_HD constexpr std::uint32_t sobol_matrix_column(std::uint32_t dimension, std::uint32_t bit) {
  if (dimension == 0) return 0x80000000U >> bit;
  std::uint32_t column = 0x80000000U;
  for (std::uint32_t k = 0; k < bit; ++k) column ^= column >> 1;
  return column;
}

// Sobol dimensions 0 and 1 of `index`, unscrambled, as 32-bit binary fractions. Dimension
// 1's columns are generated on the fly instead of read from a table, so the device needs
// no constant memory for them.
TESSERA_HD TESSERA_INLINE void sobol_2d(std::uint32_t index, std::uint32_t& x, std::uint32_t& y) {
  x = reverse_bits(index);
  y = 0;
  for (std::uint32_t column = 0x80000000U; index != 0; index >>= 1, column ^= column >> 1)
    y ^= column & (0U - (index & 1U));
}

// A permutation of 32-bit values in which every bit changes only as a function of itself,
// the bits below it and the seed: each step adds, multiplies by an odd number, or XORs in
// a product with an even number (whose bit k depends on bits below k only), and each step
// is invertible. The constants are Burley's improved ones (better avalanche than Laine and
// Karras's original).
TESSERA_HD TESSERA_INLINE std::uint32_t laine_karras_permutation(std::uint32_t x,
                                                                 std::uint32_t seed) {
  x ^= x * 0x3d20adeaU;
  x += seed;
  x *= (seed >> 16) | 1U;
  x ^= x * 0x05526c56U;
  x ^= x * 0x53a22864U;
  return x;
}

// Owen's nested uniform scramble of a 32-bit binary fraction, with the hash standing in
// for the random tree of flips: on the mirrored bits the permutation above makes each
// binary digit of the result depend only on that digit and the more significant ones, so
// values sharing their first k digits still share them afterwards (elementary intervals
// map onto elementary intervals of the same size, keeping nets nets).
TESSERA_HD TESSERA_INLINE std::uint32_t nested_uniform_scramble(std::uint32_t x,
                                                                std::uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The seed of one pixel's sample sets; the pair seeds derive from it.
TESSERA_HD TESSERA_INLINE std::uint32_t sobol_pixel_key(std::uint64_t seed, std::uint32_t pixel_x,
                                                        std::uint32_t pixel_y) {
  std::uint32_t h = mix32(static_cast<std::uint32_t>(seed) ^ 0x68e31da4U);
  h = hash_combine(h, static_cast<std::uint32_t>(seed >> 32));
  h = hash_combine(h, pixel_x);
  return hash_combine(h, pixel_y);
}

inline constexpr std::uint32_t kSobolIndexBits = 16;
inline constexpr std::uint32_t kSobolIndexMask = (1u << kSobolIndexBits) - 1u;

// Dimension 1 of a 16-bit index with its bits mirrored (bit k is the 2^-(32-k) digit), by
// two byte tables of mirrored columns: the per-pair path below scrambles in the mirrored
// domain, so it never needs the value the right way round. The device, which would need
// the tables in constant memory, runs the column loop instead.
#if !defined(__CUDA_ARCH__)
struct SobolMirroredColumns {
  std::uint32_t low[256];
  std::uint32_t high[256];
};
constexpr SobolMirroredColumns make_sobol_mirrored_columns() {
  SobolMirroredColumns t{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t low = 0, high = 0;
    for (std::uint32_t bit = 0; bit < 8; ++bit)
      if ((byte >> bit) & 1U) {
        low ^= sobol_matrix_column(1, bit);
        high ^= sobol_matrix_column(1, bit + 8);
      }
    t.low[byte] = reverse_bits(low);
    t.high[byte] = reverse_bits(high);
  }
  return t;
}
inline constexpr SobolMirroredColumns kSobolMirroredColumns = make_sobol_mirrored_columns();
#endif

TESSERA_HD TESSERA_INLINE std::uint32_t sobol_dimension1_mirrored(std::uint32_t index16) {
#if defined(__CUDA_ARCH__)
  std::uint32_t x = 0, y = 0;
  sobol_2d(index16, x, y);
  return reverse_bits(y);
#else
  return kSobolMirroredColumns.low[index16 & 0xffU] ^ kSobolMirroredColumns.high[index16 >> 8];
#endif
}

// The seeds a pair's values start from: the index shuffle's, the two coordinate scrambles'
// and the two scrambles of the pair joined to it (sobol_joined_from_index_mirrored). They
// depend on the pixel key and the pair, not on the sample index, so a pixel's samples can
// share them (SobolSeedMemo). The shuffle and the coordinate scrambles take different seeds:
// scrambling the index and a coordinate with the same one would tie them together.
struct SobolPairSeeds {
  std::uint32_t shuffle = 0;
  std::uint32_t x = 0, y = 0;
  std::uint32_t joined_x = 0, joined_y = 0;
};

TESSERA_HD TESSERA_FORCE_INLINE SobolPairSeeds sobol_pair_seeds(std::uint32_t pixel_key,
                                                                std::uint32_t pair) {
  const std::uint32_t shuffle = hash_combine(pixel_key, pair);
  return SobolPairSeeds{shuffle, hash_combine(shuffle, 1U), hash_combine(shuffle, 2U),
                        hash_combine(shuffle, 3U), hash_combine(shuffle, 4U)};
}

// The per-pixel, per-pair shuffle of the sample index that both a pair
// (sobol_pair_from_index_mirrored) and the pair joined to it (sobol_joined_from_index_mirrored)
// start from: the shuffled 16-bit Sobol index, from the sample index with its bits mirrored
// (reverse_bits), which a sample stream forms once for all its pairs.
TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t sobol_shuffled_index(
    std::uint32_t shuffle_seed, std::uint32_t mirrored_sample_index) {
  // Sample indices stay below 2^16 (SceneLimits::max_samples_per_pixel). The scramble's
  // low 16 bits depend only on the index's low 16 bits, so they are a nested uniform
  // shuffle of [0, 2^16) on their own; keeping only them lets 16-bit tables give the point.
  // nested_uniform_scramble(index) is reverse(permutation(mirrored index)).
  return reverse_high_16_bits(laine_karras_permutation(mirrored_sample_index, shuffle_seed));
}

// Dimensions 2 * pair and 2 * pair + 1 of one pixel's sample, as 32-bit binary fractions
// with their bits mirrored (reverse_bits gives the fractions; unit_float_from_mirrored the
// floats), from the pair's shuffled index and its coordinate seeds (SobolPairSeeds::x, y).
TESSERA_HD TESSERA_FORCE_INLINE void sobol_pair_from_index_mirrored(std::uint32_t index,
                                                                    std::uint32_t x_seed,
                                                                    std::uint32_t y_seed,
                                                                    std::uint32_t& mx,
                                                                    std::uint32_t& my) {
  // nested_uniform_scramble(v) is reverse(permutation(reverse(v))): dimension 0 is the
  // mirrored index, so its scramble's mirror is permutation(index), and dimension 1 is
  // produced mirrored, so neither needs a mirror before the permutation.
  mx = laine_karras_permutation(index, x_seed);
  my = laine_karras_permutation(sobol_dimension1_mirrored(index), y_seed);
}

TESSERA_HD TESSERA_FORCE_INLINE void sobol_pair_mirrored(std::uint32_t pixel_key,
                                                         std::uint32_t mirrored_sample_index,
                                                         std::uint32_t pair, std::uint32_t& x,
                                                         std::uint32_t& y) {
  const SobolPairSeeds seeds = sobol_pair_seeds(pixel_key, pair);
  sobol_pair_from_index_mirrored(sobol_shuffled_index(seeds.shuffle, mirrored_sample_index),
                                 seeds.x, seeds.y, x, y);
  x = reverse_bits(x);
  y = reverse_bits(y);
}

// Sobol dimensions 2 and 3 of `index`, unscrambled, as 32-bit binary fractions. Their
// columns follow Joe and Kuo's direction numbers (x^2 + x + 1 with m = 1, 3, and x^3 + x + 1
// with m = 1, 3, 1) by the recurrence v_k = v_{k-s} ^ (v_{k-s} >> s) ^ (a_j v_{k-j} for the
// polynomial's inner terms), generated as the loop goes: the device's way, and what the
// host's byte tables below are built from.
TESSERA_HD constexpr void sobol_dimensions23(std::uint32_t index, std::uint32_t& x,
                                             std::uint32_t& y) {
  x = 0;
  y = 0;
  // The last columns of each dimension, oldest first: v_{k-2}, v_{k-1} of dimension 2 and
  // v_{k-3}, v_{k-2}, v_{k-1} of dimension 3.
  std::uint32_t a0 = 0, a1 = 0, b0 = 0, b1 = 0, b2 = 0;
  for (std::uint32_t bit = 0; index != 0; ++bit, index >>= 1) {
    const std::uint32_t a = bit == 0 ? 1U << 31 : bit == 1 ? 3U << 30 : a1 ^ a0 ^ (a0 >> 2);
    const std::uint32_t b = bit == 0   ? 1U << 31
                            : bit == 1 ? 3U << 30
                            : bit == 2 ? 1U << 29
                                       : b1 ^ b0 ^ (b0 >> 3);
    if ((index & 1U) != 0) {
      x ^= a;
      y ^= b;
    }
    a0 = a1;
    a1 = a;
    b0 = b1;
    b1 = b2;
    b2 = b;
  }
}

// Sobol dimensions 2 and 3 of a 16-bit index, mirrored (as sobol_dimension1_mirrored): byte
// tables on the host (the points are linear in the index's bits, so the low and the high
// byte's points XOR together), the loop on the device.
#if !defined(__CUDA_ARCH__)
struct SobolUpperMirroredColumns {
  std::uint32_t low[2][256];
  std::uint32_t high[2][256];
};
constexpr SobolUpperMirroredColumns make_sobol_upper_mirrored_columns() {
  SobolUpperMirroredColumns t{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t x = 0, y = 0;
    sobol_dimensions23(byte, x, y);
    t.low[0][byte] = reverse_bits(x);
    t.low[1][byte] = reverse_bits(y);
    sobol_dimensions23(byte << 8, x, y);
    t.high[0][byte] = reverse_bits(x);
    t.high[1][byte] = reverse_bits(y);
  }
  return t;
}
inline constexpr SobolUpperMirroredColumns kSobolUpperMirroredColumns =
    make_sobol_upper_mirrored_columns();
#endif

TESSERA_HD TESSERA_INLINE void sobol_dimensions23_mirrored(std::uint32_t index16, std::uint32_t& x,
                                                           std::uint32_t& y) {
#if defined(__CUDA_ARCH__)
  sobol_dimensions23(index16, x, y);
  x = reverse_bits(x);
  y = reverse_bits(y);
#else
  const std::uint32_t lo = index16 & 0xffU, hi = index16 >> 8;
  x = kSobolUpperMirroredColumns.low[0][lo] ^ kSobolUpperMirroredColumns.high[0][hi];
  y = kSobolUpperMirroredColumns.low[1][lo] ^ kSobolUpperMirroredColumns.high[1][hi];
#endif
}

// Dimensions 2 and 3 of the 4D Sobol set whose dimensions 0 and 1 are the pair with this
// shuffled index (sobol_pair_from_index_mirrored), mirrored as that pair's are: the same index,
// other scrambles (the partner's SobolPairSeeds::joined_x and joined_y). The two pairs are
// then stratified jointly, not only each on its own: a direction sampled at one vertex and
// the point on a light sampled at the vertex it leads to cover their 4D domain evenly.
TESSERA_HD TESSERA_FORCE_INLINE void sobol_joined_from_index_mirrored(std::uint32_t index,
                                                                      std::uint32_t x_seed,
                                                                      std::uint32_t y_seed,
                                                                      std::uint32_t& mx,
                                                                      std::uint32_t& my) {
  std::uint32_t dx = 0, dy = 0;
  sobol_dimensions23_mirrored(index, dx, dy);
  mx = laine_karras_permutation(dx, x_seed);
  my = laine_karras_permutation(dy, y_seed);
}

// The same from the sample index as it is.
TESSERA_HD TESSERA_INLINE void sobol_pair(std::uint32_t pixel_key, std::uint32_t sample_index,
                                          std::uint32_t pair, std::uint32_t& x, std::uint32_t& y) {
  sobol_pair_mirrored(pixel_key, reverse_bits(sample_index), pair, x, y);
}

// One value in [0, 1): dimension `dimension` of sample `sample_index` of the pixel.
TESSERA_HD TESSERA_INLINE float sobol_sample(std::uint64_t seed, std::uint32_t pixel_x,
                                             std::uint32_t pixel_y, std::uint32_t sample_index,
                                             std::uint32_t dimension) {
  std::uint32_t x = 0;
  std::uint32_t y = 0;
  sobol_pair(sobol_pixel_key(seed, pixel_x, pixel_y), sample_index, dimension >> 1, x, y);
  return uint_to_unit_float((dimension & 1U) != 0 ? y : x);
}

}  // namespace tessera
