// A main() for a fuzz target where libFuzzer is not built (g++, `make test`): runs
// LLVMFuzzerTestOneInput on every file of the seed corpora given as arguments and on a
// fixed set of mutations of each (byte flips, truncations, repeated and spliced chunks,
// boundary numbers), the same every run. Not coverage-guided: it replays what libFuzzer
// found worth keeping and the neighbourhood of each seed, so a regression of a fixed
// finding fails the test suite without clang. Exit 0 when every input returned.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

constexpr int kMutationsPerSeed = 2000;

void run(const std::string& input) {
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
}

std::string mutate(const std::string& seed, const std::vector<std::string>& seeds,
                   std::mt19937& rng) {
  std::string out = seed;
  const auto pick = [&](std::size_t n) { return n == 0 ? 0 : rng() % n; };
  static const std::vector<std::string> kTokens = {
      "1e308", "-1e308", "nan",      "inf",  "-0",    "4294967295", "18446744073709551616",
      "[]",    "{}",     ":",        "- ",   "\n",    "\"",         "'",
      "&a",    "*a",     "!!binary", "\xff", "1e-300"};
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 6) {
      case 0:  // flip a bit
        if (!out.empty()) out[pick(out.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:  // truncate
        out.resize(pick(out.size() + 1));
        break;
      case 2: {  // insert a token, or a NUL byte
        const std::string token =
            rng() % 8 == 0 ? std::string(1, '\0') : kTokens[pick(kTokens.size())];
        out.insert(pick(out.size() + 1), token);
        break;
      }
      case 3: {  // repeat a chunk
        if (out.empty()) break;
        const std::size_t at = pick(out.size());
        const std::string chunk = out.substr(at, 1 + pick(64));
        out.insert(at, chunk);
        break;
      }
      case 4: {  // splice another seed's tail
        const std::string& other = seeds[pick(seeds.size())];
        out = out.substr(0, pick(out.size() + 1)) + other.substr(pick(other.size() + 1));
        break;
      }
      default:  // overwrite a byte
        if (!out.empty()) out[pick(out.size())] = static_cast<char>(rng());
        break;
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> seeds;
  for (int i = 1; i < argc; ++i)
    for (const auto& entry : std::filesystem::directory_iterator(argv[i])) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  if (seeds.empty()) {
    std::fprintf(stderr, "no seed files in the given folders\n");
    return 2;
  }
  std::mt19937 rng(20261124);
  std::size_t inputs = 0;
  for (const std::string& seed : seeds) {
    run(seed);
    ++inputs;
    for (int m = 0; m < kMutationsPerSeed; ++m, ++inputs) run(mutate(seed, seeds, rng));
  }
  std::printf("%zu inputs (%zu seeds) ran without a crash\n", inputs, seeds.size());
  return 0;
}
