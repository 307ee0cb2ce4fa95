#pragma once
#include <filesystem>
#include <optional>

namespace tessera::server {

// The CPU time a process may use, from the cgroup it runs in: a container limited to 2.5
// CPUs (docker --cpus=2.5, a Kubernetes CPU limit) still sees every core of the machine in
// std::thread::hardware_concurrency(), and threads beyond its quota only take turns.
//
// cgroup v2: "QUOTA PERIOD" (or "max PERIOD") in cpu.max. cgroup v1: cpu.cfs_quota_us
// (-1: none) and cpu.cfs_period_us. The process's cgroup is read from /proc/self/cgroup and
// every ancestor up to the hierarchy's root is checked (a limit may sit on a parent); the
// smallest quota wins. `root` is prepended to /proc and /sys so tests can feed fake files.
// Nothing when no quota applies or the files cannot be read.
std::optional<double> cgroup_cpu_quota(const std::filesystem::path& root = "/");

// CPUs in this process's affinity mask (sched_getaffinity: taskset, cpusets), or nothing
// when it cannot be read.
std::optional<unsigned> affinity_cpu_count();

// What bounds the default worker thread count.
struct CpuLimits {
  unsigned hardware = 0;             // std::thread::hardware_concurrency(); 0: unknown
  std::optional<unsigned> affinity;  // CPUs the process may be scheduled on
  std::optional<double> quota_cpus;  // cgroup CPU quota in CPUs (quota / period)
};

// min(hardware, affinity, ceil(quota)), at least 1: a quota of 2.5 CPUs gives 3 threads,
// so the half CPU is used rather than left idle.
unsigned thread_count_for(const CpuLimits& limits);

// The limits of this process (cgroup files under `root`).
CpuLimits current_cpu_limits(const std::filesystem::path& root = "/");

}  // namespace tessera::server
