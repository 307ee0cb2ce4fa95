#pragma once
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tessera {

// Allocator for the large arrays traversal reads at random (nodes, triangle blocks): arrays
// of 2 MiB or more are aligned to 2 MiB and offered to the kernel for transparent huge
// pages (madvise, as Embree does), so a walk through tens of megabytes touches a few TLB entries
// instead of thousands of 4 KiB pages. Where the kernel declines, it is an ordinary allocation.
template <typename T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;
  static constexpr std::size_t kAlignment = alignof(T) < 64 ? 64 : alignof(T);
  static std::size_t round_up(std::size_t bytes) {
    return (bytes + kHugePage - 1) / kHugePage * kHugePage;
  }

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= kHugePage) {
      // Fresh pages straight from mmap, aligned to 2 MiB by trimming an oversized mapping,
      // and advised before anything touches them (malloc'd memory may already be
      // faulted in as 4 KiB pages, which the kernel then leaves as they are).
      const std::size_t rounded = round_up(bytes);
      void* mapping = mmap(nullptr, rounded + kHugePage, PROT_READ | PROT_WRITE,
                           MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (mapping == MAP_FAILED) throw std::bad_alloc();
      const auto start = reinterpret_cast<std::uintptr_t>(mapping);
      const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
      if (aligned > start) munmap(mapping, aligned - start);
      const std::size_t tail = start + rounded + kHugePage - (aligned + rounded);
      if (tail > 0) munmap(reinterpret_cast<void*>(aligned + rounded), tail);
      madvise(reinterpret_cast<void*>(aligned), rounded, MADV_HUGEPAGE);
      return reinterpret_cast<T*>(aligned);
    }
#endif
    return static_cast<T*>(::operator new (bytes, std::align_val_t{kAlignment}));
  }

  void deallocate(T* p, std::size_t n) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (n * sizeof(T) >= kHugePage) {
      munmap(p, round_up(n * sizeof(T)));
      return;
    }
#endif
    ::operator delete (p, std::align_val_t{kAlignment});
  }

  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
};

template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace tessera
