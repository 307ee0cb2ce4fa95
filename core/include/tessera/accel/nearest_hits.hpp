#pragma once
#include <cstdint>

#include "tessera/geometry/ray.hpp"

namespace tessera {

// The list every all-hits query keeps: the `count` nearest hits so far, sorted by t, in
// hits[0, capacity). A hit no nearer than the farthest of a full list is dropped; otherwise
// it takes its place in order and, when the list was full, the farthest falls off.
// Returns whether the list is full afterwards (its last t then bounds the search).
TESSERA_HD TESSERA_INLINE bool insert_nearest(HitRecord* hits, std::uint32_t& count,
                                              std::uint32_t capacity, const HitRecord& hit) {
  std::uint32_t at;
  if (count == capacity) {
    if (!(hit.t < hits[capacity - 1].t)) return true;
    at = capacity - 1;
  } else {
    at = count++;
  }
  while (at > 0 && hit.t < hits[at - 1].t) {
    hits[at] = hits[at - 1];
    --at;
  }
  hits[at] = hit;
  return count == capacity;
}

}  // namespace tessera
