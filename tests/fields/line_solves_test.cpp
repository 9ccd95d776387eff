// The copies of the x lines' solve (portable, AVX2) against each other, bit for bit, on random
// factorisations and values: with and without face terms, periodic or not, line lengths that are
// and are not multiples of four, groups of 1 to 16 lines.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

using random_internal::InstructionSet;

internal::LineSolve RandomLineSolve(std::int64_t n, bool periodic, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.1, 0.9);
  internal::LineSolve f;
  f.off = unit(rng);
  for (std::int64_t i = 0; i < n; ++i) {
    f.inverse_pivot.push_back(unit(rng));
    f.upper.push_back(i + 1 < n ? -unit(rng) : 0.0);
  }
  f.lower_face = unit(rng);
  f.upper_face = unit(rng);
  if (periodic) {
    for (std::int64_t i = 0; i < n; ++i) f.periodic_z.push_back(unit(rng) - 0.5);
    f.periodic_corner = unit(rng);
    f.periodic_scale = unit(rng);
  }
  return f;
}

TEST(LineSolves, XLineCopiesGiveTheSameBits) {
  if (!random_internal::Supports(InstructionSet::kAvx2)) {
    GTEST_SKIP() << "this processor or build has no AVX2 copy";
  }
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> value(-1.0, 2.0);
  int compared = 0;
  for (std::int64_t n : {4, 5, 6, 7, 8, 9, 37, 100}) {
    for (bool periodic : {false, true}) {
      const internal::LineSolve f = RandomLineSolve(n, periodic, rng);
      for (int count : {1, 7, 15, 16}) {
        std::vector<double> portable(static_cast<std::size_t>(n * count));
        for (double& v : portable) v = value(rng);
        std::vector<double> avx2 = portable;
        const std::vector<double> before = portable;
        internal::SolveXLinesOn(InstructionSet::kPortable, f, portable.data(), n, count);
        internal::SolveXLinesOn(InstructionSet::kAvx2, f, avx2.data(), n, count);
        ASSERT_NE(portable, before);
        ASSERT_EQ(std::memcmp(portable.data(), avx2.data(), portable.size() * sizeof(double)), 0)
            << "n = " << n << ", periodic = " << periodic << ", lines = " << count;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 64);
}

// A line solved alone (portable) and as one of a group of sixteen (the AVX2 copy where it runs)
// gives the same bits: the solve of a line does not depend on its neighbours.
TEST(LineSolves, XLineDoesNotDependOnItsGroup) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> value(-1.0, 2.0);
  const std::int64_t n = 23;
  const internal::LineSolve f = RandomLineSolve(n, false, rng);
  std::vector<double> group(static_cast<std::size_t>(16 * n));
  for (double& v : group) v = value(rng);
  std::vector<double> alone(group.begin() + 5 * n, group.begin() + 6 * n);
  internal::SolveXLinesOn(InstructionSet::kAvx2, f, group.data(), n, 16);
  internal::SolveXLinesOn(InstructionSet::kPortable, f, alone.data(), n, 1);
  EXPECT_EQ(std::memcmp(alone.data(), group.data() + 5 * n, alone.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace moreau::fields
