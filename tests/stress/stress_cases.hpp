#pragma once
// The stress table: one row per (surface, case family), each with the bounds it must meet.
// Shared by the gtest suite (one test per row, label `stress`) and the tessera-stress
// program (prints the whole table).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace tessera::stress {

struct RowResult {
  long rays = 0;
  long reference_hits = 0;     // rays the reference says hit (within the family's interval)
  long wrong = 0;              // wrong closest-hit decisions (hit/miss or a different root)
  long all_hits_mismatch = 0;  // intersect_all: wrong count, wrong root or unsorted
  long nan = 0;                // non-finite t, position, normal or uv
  double max_relative_t = 0.0;
  long failed = 0;  // the solver reported that it has no answer (kSolverFailed): not wrong
};

// What a row must meet: NaN is never allowed.
struct Bounds {
  long max_wrong = 0;
  double max_relative_t = 1e-6;
  long max_all_hits_mismatch = 0;
};

struct Row {
  std::string surface;
  std::string family;
  int rays = 0;
  Bounds bounds;
  std::function<RowResult(int rays, std::uint64_t seed)> run;
};

std::vector<Row> all_rows();

// The rows of B-spline/NURBS patches and trimmed faces (patch_cases.cpp), with their
// bounds looked up by (surface, family).
void add_patch_rows(std::vector<Row>& rows,
                    const std::function<Bounds(const std::string&, const std::string&)>& bounds);

bool passes(const Row& row, const RowResult& result);
std::string table_header();
std::string table_line(const Row& row, const RowResult& result);

}  // namespace tessera::stress
