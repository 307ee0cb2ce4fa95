#pragma once
#include <atomic>

namespace tessera {

// Lets a caller stop a tile that is being rendered: while a TileCancelScope is alive on a
// thread, the tile loop on that thread checks the flag every few hundred samples and
// returns early once it is raised, leaving the tile incomplete (the caller must then
// discard it). Thread-local rather than a parameter because every compiled pipeline
// variant shares one function signature; passing the flag through it would touch them all.
namespace detail {
inline thread_local const std::atomic<bool>* tile_cancel_flag = nullptr;
}

class TileCancelScope {
 public:
  explicit TileCancelScope(const std::atomic<bool>* flag) : previous_(detail::tile_cancel_flag) {
    detail::tile_cancel_flag = flag;
  }
  ~TileCancelScope() { detail::tile_cancel_flag = previous_; }
  TileCancelScope(const TileCancelScope&) = delete;
  TileCancelScope& operator=(const TileCancelScope&) = delete;

 private:
  const std::atomic<bool>* previous_;
};

// The flag the current thread's tiles check, or null.
inline const std::atomic<bool>* current_tile_cancel_flag() {
  return detail::tile_cancel_flag;
}

}  // namespace tessera
