#include "server/tile_state_codec.hpp"

#include <array>
#include <cstring>
#include <stdexcept>

namespace tessera::server {
namespace {

constexpr char kMagic[4] = {'T', 'A', 'C', '1'};
constexpr std::size_t kPlaneSlots = 1 + kAovCount + 2;

// The state's planes in mask-bit order.
template <typename State>
auto planes_of(State& state) {
  using Plane =
      std::conditional_t<std::is_const_v<State>, const std::vector<float>*, std::vector<float>*>;
  std::array<Plane, kPlaneSlots> planes{};
  planes[0] = &state.sums.beauty;
  for (std::size_t i = 0; i < kAovCount; ++i) planes[1 + i] = &state.sums.aovs[i];
  planes[1 + kAovCount] = &state.running_mean;
  planes[2 + kAovCount] = &state.running_m2;
  return planes;
}

void put(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8)
    out.push_back(static_cast<std::uint8_t>(value >> shift));
}

}  // namespace

std::vector<std::uint8_t> encode_tile_state(const TileAccumulation& state) {
  const auto planes = planes_of(state);
  std::uint32_t mask = 0;
  std::size_t floats = 0;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (planes[i]->empty()) continue;
    if (floats != 0 && planes[i]->size() != floats)
      throw std::invalid_argument("encode_tile_state: planes of different sizes");
    floats = planes[i]->size();
    mask |= 1u << i;
  }
  std::vector<std::uint8_t> out(kMagic, kMagic + 4);
  put(out, state.samples_done);
  put(out, state.samples_total);
  put(out, static_cast<std::uint32_t>(floats));
  put(out, mask);
  for (const auto* plane : planes) {
    if (plane->empty()) continue;
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(plane->data());
    out.insert(out.end(), bytes, bytes + plane->size() * sizeof(float));
  }
  return out;
}

TileAccumulation decode_tile_state(const std::vector<std::uint8_t>& bytes) {
  constexpr std::size_t kHeader = 4 + 4 * 4;
  if (bytes.size() < kHeader || std::memcmp(bytes.data(), kMagic, 4) != 0)
    throw std::runtime_error("tile state: not a tile state record");
  const auto get = [&](std::size_t at) {
    std::uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = (value << 8) | bytes[at + static_cast<std::size_t>(i)];
    return value;
  };
  TileAccumulation state;
  state.samples_done = get(4);
  state.samples_total = get(8);
  const std::size_t floats = get(12);
  const std::uint32_t mask = get(16);
  if (mask >> kPlaneSlots != 0) throw std::runtime_error("tile state: unknown planes");
  std::size_t present = 0;
  for (std::size_t i = 0; i < kPlaneSlots; ++i) present += (mask >> i) & 1u;
  if (bytes.size() != kHeader + present * floats * sizeof(float))
    throw std::runtime_error("tile state: " + std::to_string(bytes.size()) +
                             " bytes do not hold its planes");
  std::size_t at = kHeader;
  const auto planes = planes_of(state);
  for (std::size_t i = 0; i < kPlaneSlots; ++i) {
    if (((mask >> i) & 1u) == 0) continue;
    planes[i]->resize(floats);
    std::memcpy(planes[i]->data(), bytes.data() + at, floats * sizeof(float));
    at += floats * sizeof(float);
  }
  return state;
}

}  // namespace tessera::server
