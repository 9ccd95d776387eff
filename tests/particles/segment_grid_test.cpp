// SegmentGrid (src/particles/segment_grid.h): every segment closer than the cut-off to a point
// is listed for the point's cell, in index order; a point outside the grid is farther than the
// cut-off from every segment; and exp is +0 below −745.2, the premise of the collision-free
// walls' skip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "particles/segment_grid.h"

namespace moreau::particles::internal {
namespace {

double SegmentDistance(const double* x, const double* a, const double* b) {
  const double e0 = b[0] - a[0], e1 = b[1] - a[1];
  const double t =
      std::clamp(((x[0] - a[0]) * e0 + (x[1] - a[1]) * e1) / (e0 * e0 + e1 * e1), 0.0, 1.0);
  return std::hypot(x[0] - (a[0] + t * e0), x[1] - (a[1] + t * e1));
}

TEST(SegmentGrid, ListsEverySegmentWithinTheCutOffInIndexOrder) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> where(0.0, 100.0), step(-8.0, 8.0);
  std::vector<double> a, b;
  for (int s = 0; s < 40; ++s) {
    const double x = where(rng), y = where(rng);
    a.insert(a.end(), {x, y});
    b.insert(b.end(), {x + step(rng), y + step(rng)});
  }
  for (const double cut : {0.3, 5.0, 75.0}) {
    const SegmentGrid grid(a, b, cut, 64);
    ASSERT_TRUE(grid.active());
    std::uniform_real_distribution<double> point(-100.0, 200.0);
    int listed = 0;
    for (int p = 0; p < 20000; ++p) {
      const double x[2] = {point(rng), point(rng)};
      const int* first = nullptr;
      const int* last = nullptr;
      grid.Near(x, &first, &last);
      const std::vector<int> near(first, last);
      EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
      EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
      for (int s = 0; s < 40; ++s) {
        if (SegmentDistance(x, &a[2 * s], &b[2 * s]) > cut) continue;
        ++listed;
        EXPECT_TRUE(std::binary_search(near.begin(), near.end(), s))
            << "segment " << s << " at (" << x[0] << ", " << x[1] << "), cut " << cut;
      }
    }
    EXPECT_GT(listed, 0);
  }
}

TEST(SegmentGrid, NoSegmentsOrNoReachMeansNoGrid) {
  EXPECT_FALSE(SegmentGrid({}, {}, 1.0, 64).active());
  EXPECT_FALSE(SegmentGrid({0.0, 0.0}, {1.0, 0.0}, std::nan(""), 64).active());
}

TEST(SegmentGrid, ExpIsZeroBelowTheSkipThreshold) {
  // The collision-free walls skip terms whose exponent is below −746: exp gives +0 there.
  EXPECT_EQ(std::exp(-745.2), 0.0);
  EXPECT_EQ(std::exp(-746.0), 0.0);
  EXPECT_GT(std::exp(-744.4), 0.0);
}

}  // namespace
}  // namespace moreau::particles::internal
