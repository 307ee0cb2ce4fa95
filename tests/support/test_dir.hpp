#pragma once
// A folder of its own for each test under the system's temporary directory. ctest runs
// tests in parallel, one process each, so the name holds the suite, the test and the
// process id.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace tessera::test {

// `<temp>/<prefix>-<suite>-<pid>-<test>`, emptied and created. Parameterised names lose
// their slashes, so the folder is one level deep and removing it leaves nothing behind.
inline std::filesystem::path make_test_dir(const std::string& prefix = "tessera") {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = prefix + "-" + test->test_suite_name() + "-" + std::to_string(::getpid()) +
                     "-" + test->name();
  std::replace(name.begin(), name.end(), '/', '_');
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A fixture whose every test has `dir_`, made empty before the test and removed after it.
class TestDirFixture : public ::testing::Test {
 protected:
  explicit TestDirFixture(std::string prefix = "tessera") : prefix_(std::move(prefix)) {}

  void SetUp() override { dir_ = make_test_dir(prefix_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace tessera::test
