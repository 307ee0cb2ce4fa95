#pragma once
#include <atomic>
#include <cstdint>
#include <string>

namespace tessera::server {

// Makes short job ids, `job-` + 12 hex digits. A counter passes through a bijection of
// 48-bit numbers keyed by a random value drawn at start, so ids never repeat within one
// daemon (2^48 of them) and do not collide across restarts in practice, while not giving
// away how many jobs were submitted.
class JobIdGenerator {
 public:
  JobIdGenerator();  // random key
  explicit JobIdGenerator(std::uint64_t key);

  std::string next();

 private:
  std::uint64_t key_;
  std::atomic<std::uint64_t> counter_{0};
};

}  // namespace tessera::server
