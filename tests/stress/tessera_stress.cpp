// tessera-stress: runs every stress row and prints the table
// (surface x case family x rays x wrong decisions x max relative t error), then
// "N passed, M failed". Exit status 0 only when every row meets its bounds.
//   tessera-stress [--filter SUBSTRING] [--rays-scale FACTOR] [--seed N]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "stress_cases.hpp"

int main(int argc, char** argv) {
  std::string filter;
  double rays_scale = 1.0;
  std::uint64_t seed = 20240601;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--filter") == 0 && i + 1 < argc) {
      filter = argv[++i];
    } else if (std::strcmp(argv[i], "--rays-scale") == 0 && i + 1 < argc) {
      rays_scale = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else {
      std::fprintf(stderr, "usage: %s [--filter SUBSTRING] [--rays-scale FACTOR] [--seed N]\n",
                   argv[0]);
      return 2;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  int passed = 0, failed = 0;
  std::printf("%s\n", tessera::stress::table_header().c_str());
  std::uint64_t row_seed = seed;
  for (const auto& row : tessera::stress::all_rows()) {
    ++row_seed;
    if (!filter.empty() && (row.surface + " " + row.family).find(filter) == std::string::npos)
      continue;
    const int rays = std::max(1, static_cast<int>(row.rays * rays_scale));
    const auto result = row.run(rays, row_seed);
    std::printf("%s\n", tessera::stress::table_line(row, result).c_str());
    std::fflush(stdout);
    (tessera::stress::passes(row, result) ? passed : failed)++;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("(%.1f s)\n%d passed, %d failed\n", seconds, passed, failed);
  return failed == 0 ? 0 : 1;
}
