#include "server/cpu_limits.hpp"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace tessera::server {
namespace {

std::optional<std::string> read_first_line(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line)) return std::nullopt;
  return line;
}

std::optional<long long> read_integer(const std::filesystem::path& file) {
  const auto line = read_first_line(file);
  if (!line) return std::nullopt;
  try {
    return std::stoll(*line);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// cgroup v2 cpu.max: "max 100000" (no quota) or "250000 100000".
std::optional<double> v2_quota(const std::filesystem::path& dir) {
  const auto line = read_first_line(dir / "cpu.max");
  if (!line) return std::nullopt;
  std::istringstream fields(*line);
  std::string quota;
  long long period = 0;
  if (!(fields >> quota >> period) || quota == "max" || period <= 0) return std::nullopt;
  try {
    const long long q = std::stoll(quota);
    if (q <= 0) return std::nullopt;
    return static_cast<double>(q) / static_cast<double>(period);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// cgroup v1: cpu.cfs_quota_us (-1: no quota) over cpu.cfs_period_us.
std::optional<double> v1_quota(const std::filesystem::path& dir) {
  const auto quota = read_integer(dir / "cpu.cfs_quota_us");
  const auto period = read_integer(dir / "cpu.cfs_period_us");
  if (!quota || !period || *quota <= 0 || *period <= 0) return std::nullopt;
  return static_cast<double>(*quota) / static_cast<double>(*period);
}

std::optional<double> smaller(std::optional<double> a, std::optional<double> b) {
  if (!a) return b;
  if (!b) return a;
  return std::min(*a, *b);
}

// The smallest quota from `mount`/`cgroup_path` up to `mount` itself. Inside a container
// /proc/self/cgroup may name the host's path while the container sees its own cgroup at
// the mount point: a path that does not exist under the mount starts at the mount.
template <typename ReadQuota>
std::optional<double> quota_up_the_tree(const std::filesystem::path& mount,
                                        const std::string& cgroup_path, ReadQuota read_quota) {
  std::filesystem::path relative = std::filesystem::path(cgroup_path).relative_path();
  relative = relative.lexically_normal();
  std::error_code ec;
  if (relative.empty() || relative == "." || !std::filesystem::is_directory(mount / relative, ec))
    relative.clear();
  std::optional<double> quota;
  for (;;) {
    quota = smaller(quota, read_quota(relative.empty() ? mount : mount / relative));
    if (relative.empty()) break;
    relative = relative.parent_path();
  }
  return quota;
}

}  // namespace

std::optional<double> cgroup_cpu_quota(const std::filesystem::path& root) {
  const std::filesystem::path sys_cgroup = root / "sys/fs/cgroup";
  std::string v2_path;
  std::string v1_path;
  bool v2_listed = false;
  bool v1_listed = false;
  std::ifstream self(root / "proc/self/cgroup");
  std::string line;
  // Lines are "ID:CONTROLLERS:PATH"; v2's unified hierarchy is "0::PATH".
  while (std::getline(self, line)) {
    const auto first = line.find(':');
    const auto second = first == std::string::npos ? first : line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string path = line.substr(second + 1);
    if (controllers.empty()) {
      v2_path = path;
      v2_listed = true;
    } else {
      std::istringstream names(controllers);
      std::string name;
      while (std::getline(names, name, ','))
        if (name == "cpu") {
          v1_path = path;
          v1_listed = true;
        }
    }
  }
  std::optional<double> quota;
  std::error_code ec;
  if (v1_listed || !v2_listed) {
    for (const char* mount : {"cpu,cpuacct", "cpu"}) {
      const std::filesystem::path dir = sys_cgroup / mount;
      if (std::filesystem::is_directory(dir, ec)) {
        quota = smaller(quota, quota_up_the_tree(dir, v1_path, v1_quota));
        break;
      }
    }
  }
  if (v2_listed || !v1_listed)
    quota = smaller(quota, quota_up_the_tree(sys_cgroup, v2_path, v2_quota));
  return quota;
}

std::optional<unsigned> affinity_cpu_count() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return std::nullopt;
  const int count = CPU_COUNT(&set);
  if (count <= 0) return std::nullopt;
  return static_cast<unsigned>(count);
}

unsigned thread_count_for(const CpuLimits& limits) {
  unsigned threads = limits.hardware == 0 ? 1 : limits.hardware;
  if (limits.affinity && *limits.affinity > 0) threads = std::min(threads, *limits.affinity);
  if (limits.quota_cpus && *limits.quota_cpus > 0.0) {
    const double quota = std::ceil(*limits.quota_cpus);
    if (quota < static_cast<double>(threads)) threads = static_cast<unsigned>(quota);
  }
  return std::max(threads, 1u);
}

CpuLimits current_cpu_limits(const std::filesystem::path& root) {
  CpuLimits limits;
  limits.hardware = std::thread::hardware_concurrency();
  limits.affinity = affinity_cpu_count();
  limits.quota_cpus = cgroup_cpu_quota(root);
  return limits;
}

}  // namespace tessera::server
