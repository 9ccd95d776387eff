// The initial state's checks against many segment obstacles (initial_state.h): with more than a
// few segments each particle looks only at those near it (binned on a grid), and the answers must
// be those of the loop over every segment: no placed particle inside any segment, the same
// placement whatever segments lie far away, and the first segment in index order named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "moreau/particles/initial_state.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

// dist(x, [a, b]) in 2D.
double SegmentDistance(const double* x, const SegmentObstacle& s) {
  const double e0 = s.b[0] - s.a[0], e1 = s.b[1] - s.a[1];
  const double t =
      std::clamp(((x[0] - s.a[0]) * e0 + (x[1] - s.a[1]) * e1) / (e0 * e0 + e1 * e1), 0.0, 1.0);
  return std::hypot(x[0] - s.a[0] - t * e0, x[1] - s.a[1] - t * e1);
}

// 300 disks of radius 0.15 in a 20 × 10 box with 40 teeth: vertical segments 0.5 apart.
ParticleModel Comb() {
  ParticleModel m;
  m.dimension = 2;
  m.radius.assign(300, 0.15);
  m.AddBoxWalls({0, 0, 0}, {20, 10, 0});
  for (int j = 0; j < 40; ++j) {
    const double x = 0.5 * j + 0.25;
    m.segments.push_back(SegmentObstacle{{x, 1.0}, {x, 6.0}});
  }
  return m;
}

TEST(InitialState, BinnedSegmentsAnswerAsTheLoopOverAll) {
  const ParticleModel comb = Comb();
  const std::vector<double> x = RandomSequentialAddition(comb, {0, 0, 0}, {20, 10, 0}, 7);
  int between_teeth = 0;
  for (int i = 0; i < comb.count(); ++i) {
    const double* xi = &x[static_cast<std::size_t>(2 * i)];
    for (const SegmentObstacle& s : comb.segments) ASSERT_GE(SegmentDistance(xi, s), 0.15 - 1e-12);
    between_teeth += xi[1] > 1.0 && xi[1] < 6.0 ? 1 : 0;
  }
  EXPECT_GT(between_teeth, 20);  // the teeth were in the way of some draws
  EXPECT_NO_THROW(CheckInitialState(comb, x, 0.0));

  // Segments far from the box change no draw's answer.
  ParticleModel far = comb;
  for (int j = 0; j < 40; ++j) {
    far.segments.push_back(SegmentObstacle{{100.0 + j, 50.0}, {100.0 + j, 60.0}});
  }
  EXPECT_EQ(RandomSequentialAddition(far, {0, 0, 0}, {20, 10, 0}, 7), x);

  // A particle across teeth 17 and 18 (crossing segments added after them): the first named.
  std::vector<double> bad = x;
  ParticleModel crossed = comb;
  crossed.segments.push_back(SegmentObstacle{{8.0, 3.0}, {10.0, 3.0}});
  bad[0] = 0.5 * 17 + 0.25 + 0.1;
  bad[1] = 3.0;
  ExpectInputError([&] { CheckInitialState(crossed, bad, 0.0); },
                   "particle 0 is inside segments[17]");
  bad[0] = 9.0;  // between teeth 17 and 18, on the crossing segment alone
  ExpectInputError([&] { CheckInitialState(crossed, bad, 0.0); },
                   "particle 0 is inside segments[40]");
}

}  // namespace
}  // namespace moreau::particles
