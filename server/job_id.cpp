#include "server/job_id.hpp"

#include <cstdio>
#include <random>

namespace tessera::server {
namespace {

constexpr std::uint64_t kMask48 = (std::uint64_t{1} << 48) - 1;

// Each step is invertible modulo 2^48 (odd multipliers, xor-shifts, adding a constant), so
// distinct counters give distinct ids.
std::uint64_t permute48(std::uint64_t x, std::uint64_t key) {
  x = (x + key) & kMask48;
  x = (x * 0x9E3779B97F4Bull) & kMask48;
  x ^= x >> 24;
  x = (x * 0xBF58476D1CE5ull) & kMask48;
  x ^= x >> 21;
  x = ((x ^ (key >> 16)) * 0x94D049BB1331ull) & kMask48;
  x ^= x >> 25;
  return x;
}

std::uint64_t random_key() {
  std::random_device device;
  return (static_cast<std::uint64_t>(device()) << 32) ^ device();
}

}  // namespace

JobIdGenerator::JobIdGenerator() : JobIdGenerator(random_key()) {}
JobIdGenerator::JobIdGenerator(std::uint64_t key) : key_(key) {}

std::string JobIdGenerator::next() {
  const std::uint64_t value = permute48(counter_.fetch_add(1), key_);
  char text[4 + 12 + 1];
  std::snprintf(text, sizeof text, "job-%012llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace tessera::server
