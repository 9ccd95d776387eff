// The exits' distance field (routing.h) against exact walking distances: a convex room (the
// Euclidean distance to the door segment), a pillar (the geodesic around its corner); its
// first-order convergence, the unit directions and the walk out through an exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/routing.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

// A 4 m × 3 m room with a 1 m door in the right wall.
CrowdGeometry DoorRoom() {
  CrowdGeometry g;
  g.walkable = {{0.0, 0.0}, {4.0, 0.0}, {4.0, 3.0}, {0.0, 3.0}};
  g.exits = {{{4.0, 1.0}, {4.0, 2.0}}};
  return g;
}

// The largest |d_h − d| over the nodes strictly inside the room (the room is convex, so the
// walking distance is the Euclidean distance to the door segment).
double MaxErrorInDoorRoom(double h) {
  const CrowdGeometry g = DoorRoom();
  const DistanceField field(g, RoutingOptions{h, 0.0});
  double worst = 0.0;
  int nodes = 0;
  for (int j = 0; j < field.ny(); ++j) {
    for (int i = 0; i < field.nx(); ++i) {
      const double x = -h + i * h, y = -h + j * h;
      if (!(x > 1e-9 && x < 4.0 - 1e-9 && y > 1e-9 && y < 3.0 - 1e-9)) continue;
      const double d = field.NodeDistance(i, j);
      EXPECT_TRUE(std::isfinite(d)) << "node (" << x << ", " << y << ") not reached";
      worst = std::max(worst, std::abs(d - DistanceToSegment({x, y}, g.exits[0].a, g.exits[0].b)));
      ++nodes;
    }
  }
  EXPECT_GT(nodes, 0);
  return worst;
}

// First order: first-order fast marching converges as h log(1/h) where the front starts from a
// point (the door's ends: Sethian 1996; Zhao 2005), so the bound is 0.5 h ln(L/h), L = 4 m the
// room's size, and the observed order log2(e(h)/e(h/2)) is at least 0.5.
TEST(DistanceField, ConvergesAtFirstOrderToTheDistanceToTheDoor) {
  const double e1 = MaxErrorInDoorRoom(0.1);
  const double e2 = MaxErrorInDoorRoom(0.05);
  const double e3 = MaxErrorInDoorRoom(0.025);
  std::printf("door room: max error %.3e, %.3e, %.3e at h = 0.1, 0.05, 0.025\n", e1, e2, e3);
  EXPECT_LT(e1, 0.5 * 0.1 * std::log(4.0 / 0.1));
  EXPECT_LT(e2, 0.5 * 0.05 * std::log(4.0 / 0.05));
  EXPECT_LT(e3, 0.5 * 0.025 * std::log(4.0 / 0.025));
  EXPECT_GT(std::log2(e1 / e2), 0.5) << e1 << " " << e2;
  EXPECT_GT(std::log2(e2 / e3), 0.5) << e2 << " " << e3;
}

// A 10 m × 6 m room, a door at x = 10, y ∈ [2.5, 3.5], and a 2 m pillar [4, 6] × [2, 4] in the
// way of a person at (2, 3): the walking distance goes round a corner, √5 + 2 + √(4² + 0.5²).
CrowdGeometry PillarRoom() {
  CrowdGeometry g;
  g.walkable = {{0.0, 0.0}, {10.0, 0.0}, {10.0, 6.0}, {0.0, 6.0}};
  g.obstacles = {{{4.0, 2.0}, {6.0, 2.0}, {6.0, 4.0}, {4.0, 4.0}}};
  g.exits = {{{10.0, 2.5}, {10.0, 3.5}}};
  return g;
}

TEST(DistanceField, GoesRoundThePillarsCorner) {
  const double exact = std::sqrt(5.0) + 2.0 + std::hypot(4.0, 0.5);
  const double straight = 8.0;  // through the pillar, 0.27 m shorter
  double previous = 1.0;
  for (const double h : {0.1, 0.05, 0.025}) {
    const DistanceField field(PillarRoom(), RoutingOptions{h, 0.0});
    const double error = std::abs(field.Distance(2.0, 3.0) - exact);
    std::printf("pillar h = %g: d = %.5f, exact %.5f, error %.2e\n", h,
                field.Distance(2.0, 3.0), exact, error);
    EXPECT_LT(error, 2.0 * h) << "h = " << h;
    EXPECT_LT(error, previous);
    previous = error;
    EXPECT_GT(field.Distance(2.0, 3.0), straight + 0.1);
    // In front of the pillar the person heads for a corner: up or down, not into it.
    double e[2];
    const double x[2] = {3.5, 3.0};
    field.Direction(x, e);
    EXPECT_GT(std::abs(e[1]), 0.3);
  }
}

// The largest angle between the field's direction and the exact one (toward the nearest point
// of the door) over seeded random points at least 0.5 m from the door; every direction inside is
// a unit vector.
double MaxAngleError(double h) {
  const CrowdGeometry g = DoorRoom();
  const DistanceField field(g, RoutingOptions{h, 0.0});
  SplitMix64 rng(11);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    const double x[2] = {4.0 * rng.Uniform01(), 3.0 * rng.Uniform01()};
    double e[2];
    field.Direction(x, e);
    EXPECT_NEAR(std::hypot(e[0], e[1]), 1.0, 1e-12);
    const double dx = 4.0 - x[0], dy = std::clamp(x[1], 1.0, 2.0) - x[1];
    const double r = std::hypot(dx, dy);
    if (r > 0.5) {
      worst = std::max(worst, std::acos(std::min(1.0, (e[0] * dx + e[1] * dy) / r)));
    }
  }
  return worst;
}

// The directions converge at first order too; through the door the direction is the exit's
// outward normal.
TEST(DistanceField, DirectionsAreUnitAndPointToTheDoor) {
  const double a1 = MaxAngleError(0.05);
  const double a2 = MaxAngleError(0.025);
  std::printf("door room: max angle error %.3f, %.3f rad at h = 0.05, 0.025\n", a1, a2);
  EXPECT_LT(a1, 0.2);
  EXPECT_GT(a1 / a2, 1.5) << a1 << " " << a2;
  const DistanceField field(DoorRoom(), RoutingOptions{0.05, 0.0});
  double e[2];
  const double out[2] = {4.3, 2.9};
  field.Direction(out, e);
  EXPECT_EQ(e[0], 1.0);
  EXPECT_EQ(e[1], 0.0);
}

// Two doors: each point heads for the one nearer by walking distance, and d is the smaller of
// the two distances.
TEST(DistanceField, ChoosesTheNearerExit) {
  CrowdGeometry g = DoorRoom();
  g.exits.push_back({{0.0, 1.0}, {0.0, 2.0}});
  const DistanceField field(g, RoutingOptions{0.05, 0.0});
  double e[2];
  const double left[2] = {1.5, 2.5}, right[2] = {2.5, 0.5};
  field.Direction(left, e);
  EXPECT_LT(e[0], -0.5);
  field.Direction(right, e);
  EXPECT_GT(e[0], 0.5);
  EXPECT_NEAR(field.Distance(1.5, 1.5), 1.5, 0.05);
}

TEST(DistanceField, RejectsBadOptions) {
  ExpectInputError(
      [] {
        (void)DistanceField(DoorRoom(), RoutingOptions{0.0, 0.0});
      },
      "spacing: must be > 0");
  ExpectInputError(
      [] {
        (void)DistanceField(DoorRoom(), RoutingOptions{0.1, -1.0});
      },
      "clearance: must be ≥ 0");
  ExpectInputError(
      [] {
        (void)DistanceField(DoorRoom(), RoutingOptions{1e-5, 0.0});
      },
      "spacing: the grid would have");
  // The 1 m door is closed by a clearance of 0.6 m from its jambs.
  ExpectInputError(
      [] {
        (void)DistanceField(DoorRoom(), RoutingOptions{0.1, 0.6});
      },
      "clearance: no free grid node within 1.5 spacings of exit 0");
}

}  // namespace
}  // namespace moreau::particles
