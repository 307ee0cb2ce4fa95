#pragma once
// Walker's alias method: draws index i with probability weight_i / sum in O(1) from one
// uniform number, whatever the number of entries (light selection by power).
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/math/host_device.hpp"
#include "tessera/math/sampling.hpp"

namespace tessera {

struct AliasSlot {
  float threshold = 1.0f;  // keep this slot when the fraction is below it, else take `alias`
  std::uint32_t alias = 0;
};

// `u` in [0, 1) -> an index of `slots` (count > 0), and in `rest` what is left of u: its
// fraction within the slot, stretched from the part of the slot that chose the index back
// to [0, 1). Given the index, `rest` is uniform on [0, 1) (each part of [0, 1) that picks it
// covers [0, 1) once), so a sampler can take it as a coordinate.
TESSERA_HD TESSERA_INLINE std::uint32_t alias_pick(const AliasSlot* slots, std::uint32_t count,
                                                   float u, float& rest) {
  const float scaled = u * static_cast<float>(count);
  std::uint32_t i = static_cast<std::uint32_t>(scaled);
  if (i >= count) i = count - 1;
  const float fraction = scaled - static_cast<float>(i);
  const float threshold = slots[i].threshold;
  const bool own = fraction < threshold;
  // NaN (a fraction at 1 past a threshold of 1) and rounding past the ends are clamped.
  rest = clamp_below_one(own ? fraction / threshold : (fraction - threshold) / (1.0f - threshold));
  return own ? i : slots[i].alias;
}

TESSERA_HD TESSERA_INLINE std::uint32_t alias_pick(const AliasSlot* slots, std::uint32_t count,
                                                   float u) {
  float rest = 0.0f;
  return alias_pick(slots, count, u, rest);
}

// Vose's construction, in double so long lists of nearly equal weights stay exact enough.
// Zero or negative weights are never picked; all-zero weights give a uniform table.
inline std::vector<AliasSlot> build_alias_table(std::span<const double> weights) {
  const std::size_t n = weights.size();
  std::vector<AliasSlot> slots(n);
  if (n == 0) return slots;
  double total = 0.0;
  for (double w : weights) total += w > 0.0 ? w : 0.0;
  std::vector<double> scaled(n);
  for (std::size_t i = 0; i < n; ++i)
    scaled[i] =
        total > 0.0 ? (weights[i] > 0.0 ? weights[i] : 0.0) * static_cast<double>(n) / total : 1.0;
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i)
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    slots[s] = AliasSlot{static_cast<float>(scaled[s]), l};
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What is left is 1 up to rounding.
  for (std::uint32_t i : large) slots[i] = AliasSlot{1.0f, i};
  for (std::uint32_t i : small) slots[i] = AliasSlot{1.0f, i};
  return slots;
}

}  // namespace tessera
