// Default worker threads follow the CPUs the process may use: cgroup v1 and v2 quotas
// (read from fake files under a temporary root), the affinity mask and the hardware.
#include "server/cpu_limits.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace tessera::server {
namespace {

class FakeCgroupRoot : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::temp_directory_path() /
            ("tesserad-cgroup-test-" + std::to_string(::getpid()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  void write(const std::string& relative, const std::string& text) {
    const auto path = root_ / relative;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }

  std::filesystem::path root_;
};

TEST_F(FakeCgroupRoot, V2QuotaIsQuotaOverPeriod) {
  write("proc/self/cgroup", "0::/\n");
  write("sys/fs/cgroup/cpu.max", "250000 100000\n");
  const auto quota = cgroup_cpu_quota(root_);
  ASSERT_TRUE(quota);
  EXPECT_DOUBLE_EQ(*quota, 2.5);
}

TEST_F(FakeCgroupRoot, V2MaxMeansNoQuota) {
  write("proc/self/cgroup", "0::/\n");
  write("sys/fs/cgroup/cpu.max", "max 100000\n");
  EXPECT_FALSE(cgroup_cpu_quota(root_));
}

TEST_F(FakeCgroupRoot, V2TheSmallestQuotaOnThePathToTheRootWins) {
  write("proc/self/cgroup", "0::/kubepods/pod1/container\n");
  write("sys/fs/cgroup/cpu.max", "max 100000\n");
  write("sys/fs/cgroup/kubepods/cpu.max", "800000 100000\n");
  write("sys/fs/cgroup/kubepods/pod1/cpu.max", "150000 100000\n");
  write("sys/fs/cgroup/kubepods/pod1/container/cpu.max", "max 100000\n");
  const auto quota = cgroup_cpu_quota(root_);
  ASSERT_TRUE(quota);
  EXPECT_DOUBLE_EQ(*quota, 1.5);
}

TEST_F(FakeCgroupRoot, V1QuotaAndMinusOne) {
  write("proc/self/cgroup", "4:cpu,cpuacct:/\n3:memory:/\n");
  write("sys/fs/cgroup/cpu,cpuacct/cpu.cfs_quota_us", "300000\n");
  write("sys/fs/cgroup/cpu,cpuacct/cpu.cfs_period_us", "100000\n");
  const auto quota = cgroup_cpu_quota(root_);
  ASSERT_TRUE(quota);
  EXPECT_DOUBLE_EQ(*quota, 3.0);

  write("sys/fs/cgroup/cpu,cpuacct/cpu.cfs_quota_us", "-1\n");
  EXPECT_FALSE(cgroup_cpu_quota(root_));
}

TEST_F(FakeCgroupRoot, V1HostPathMissingInsideTheContainerFallsBackToTheMount) {
  // Without a cgroup namespace /proc/self/cgroup names the host's path, which the
  // container's mount does not have: its own cgroup is the mount itself.
  write("proc/self/cgroup", "4:cpu,cpuacct:/docker/0123abcd\n");
  write("sys/fs/cgroup/cpu,cpuacct/cpu.cfs_quota_us", "50000\n");
  write("sys/fs/cgroup/cpu,cpuacct/cpu.cfs_period_us", "100000\n");
  const auto quota = cgroup_cpu_quota(root_);
  ASSERT_TRUE(quota);
  EXPECT_DOUBLE_EQ(*quota, 0.5);
}

TEST_F(FakeCgroupRoot, NoFilesMeansNoQuota) {
  std::filesystem::create_directories(root_);
  EXPECT_FALSE(cgroup_cpu_quota(root_));
  write("proc/self/cgroup", "0::/\n");
  write("sys/fs/cgroup/cpu.max", "garbage\n");
  EXPECT_FALSE(cgroup_cpu_quota(root_));
}

TEST(ThreadCount, IsTheSmallestOfHardwareAffinityAndRoundedUpQuota) {
  EXPECT_EQ(
      thread_count_for({.hardware = 16, .affinity = std::nullopt, .quota_cpus = std::nullopt}),
      16u);
  EXPECT_EQ(thread_count_for({.hardware = 16, .affinity = 4, .quota_cpus = std::nullopt}), 4u);
  EXPECT_EQ(thread_count_for({.hardware = 16, .affinity = 8, .quota_cpus = 2.5}), 3u);
  EXPECT_EQ(thread_count_for({.hardware = 16, .affinity = 2, .quota_cpus = 6.0}), 2u);
  EXPECT_EQ(thread_count_for({.hardware = 4, .affinity = 4, .quota_cpus = 32.0}), 4u);
  EXPECT_EQ(thread_count_for({.hardware = 16, .affinity = 16, .quota_cpus = 0.1}), 1u);
  EXPECT_EQ(thread_count_for({.hardware = 0, .affinity = std::nullopt, .quota_cpus = std::nullopt}),
            1u);
}

TEST(ThreadCount, ThisProcessGetsAtLeastOneAndNoMoreThanItsAffinity) {
  const CpuLimits limits = current_cpu_limits();
  const unsigned threads = thread_count_for(limits);
  EXPECT_GE(threads, 1u);
  if (limits.affinity) {
    EXPECT_LE(threads, *limits.affinity);
  }
}

}  // namespace
}  // namespace tessera::server
