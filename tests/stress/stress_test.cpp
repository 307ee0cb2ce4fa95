// One GoogleTest per stress row (CTest label `stress`): each row's rays are checked
// against the quad-precision reference and must meet the bounds in stress_cases.cpp.
#include <gtest/gtest.h>

#include <string>

#include "stress_cases.hpp"

namespace {

using tessera::stress::Row;

class StressRow : public ::testing::TestWithParam<int> {};

const std::vector<Row>& rows() {
  static const std::vector<Row> all = tessera::stress::all_rows();
  return all;
}

TEST_P(StressRow, MeetsBounds) {
  const Row& row = rows()[static_cast<std::size_t>(GetParam())];
  // Same seeds as tessera-stress, so the test reproduces the printed table.
  const auto result = row.run(row.rays, 20240601 + 1 + static_cast<std::uint64_t>(GetParam()));
  SCOPED_TRACE(tessera::stress::table_header());
  SCOPED_TRACE(tessera::stress::table_line(row, result));
  EXPECT_EQ(result.nan, 0);
  EXPECT_LE(result.wrong, row.bounds.max_wrong);
  EXPECT_LE(result.all_hits_mismatch, row.bounds.max_all_hits_mismatch);
  EXPECT_LE(result.max_relative_t, row.bounds.max_relative_t);
}

std::string row_name(const ::testing::TestParamInfo<int>& info) {
  const Row& row = rows()[static_cast<std::size_t>(info.param)];
  std::string name = row.surface + "_" + row.family;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return std::to_string(info.param) + "_" + name;
}

INSTANTIATE_TEST_SUITE_P(Table, StressRow, ::testing::Range(0, static_cast<int>(rows().size())),
                         row_name);

}  // namespace
