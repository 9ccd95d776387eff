// A crowd's geometry (geometry.h): the text format and its errors (file, line, reason), the
// checks of the polygons and exits, the walls it gives and the evacuation count per exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "moreau/particles/geometry.h"
#include "moreau/particles/room.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

// A 10 m × 6 m room, a 2 m × 2 m pillar, a door on the left and one on the right.
constexpr const char* kTwoExits =
    "# two exits and a pillar\n"
    "walkable 0 0 10 0 10 6 0 6\n"
    "\n"
    "obstacle 4 2 6 2 6 4 4 4   # the pillar\n"
    "exit 10 2.5 10 3.5\n"
    "exit 0 1 0 2\n";

TEST(CrowdGeometry, ParsesPolygonsExitsAndComments) {
  const CrowdGeometry g = ParseCrowdGeometry(kTwoExits, "room.txt");
  ASSERT_EQ(g.walkable.size(), 4u);
  ASSERT_EQ(g.obstacles.size(), 1u);
  EXPECT_EQ(g.obstacles[0][2], (Point2{6.0, 4.0}));
  ASSERT_EQ(g.exits.size(), 2u);
  EXPECT_EQ(g.exits[1].b, (Point2{0.0, 2.0}));
  EXPECT_TRUE(g.Walkable(1.0, 1.0));
  EXPECT_FALSE(g.Walkable(5.0, 3.0));   // in the pillar
  EXPECT_FALSE(g.Walkable(11.0, 3.0));  // outside
  EXPECT_TRUE(g.InsideWalkablePolygon(5.0, 3.0));
}

// The walls are the polygon's edges with the exits cut out, then the pillar's four edges; their
// total length is the perimeters less the exits' widths.
TEST(CrowdGeometry, WallsLeaveTheExitsOpen) {
  const CrowdGeometry g = ParseCrowdGeometry(kTwoExits, "room.txt");
  const std::vector<SegmentObstacle> walls = g.Walls();
  EXPECT_EQ(walls.size(), 6u + 4u);
  double length = 0.0;
  for (const SegmentObstacle& w : walls) length += std::hypot(w.b[0] - w.a[0], w.b[1] - w.a[1]);
  EXPECT_NEAR(length, 32.0 - 2.0 + 8.0, 1e-12);
  for (const SegmentObstacle& w : walls) {
    // No wall covers an exit's midpoint.
    EXPECT_GT(DistanceToSegment({10.0, 3.0}, {w.a[0], w.a[1]}, {w.b[0], w.b[1]}), 0.4);
    EXPECT_GT(DistanceToSegment({0.0, 1.5}, {w.a[0], w.a[1]}, {w.b[0], w.b[1]}), 0.4);
  }
  EXPECT_EQ(g.ExitNormal(0), (Point2{1.0, 0.0}));
  EXPECT_EQ(g.ExitNormal(1), (Point2{-1.0, 0.0}));
  EXPECT_EQ(g.NearestExit(9.0, 3.0), 0u);
  EXPECT_EQ(g.NearestExit(1.0, 3.0), 1u);
}

TEST(CrowdGeometry, BadFilesNameTheFileTheLineAndTheReason) {
  const auto parse = [](const std::string& text) {
    return [text] { (void)ParseCrowdGeometry(text, "room.txt"); };
  };
  ExpectInputError(parse("walkable 0 0 1 0 1 nan\nexit 1 0 1 1\n"),
                   "room.txt:1: nan is not a finite number");
  ExpectInputError(parse("walkable 0 0 1 0 1 1e999\n"), "room.txt:1: 1e999 is not a finite");
  ExpectInputError(parse("walkable 0 0 4 0 4 4 0 4\nobstacle 1 1 2 2\nexit 4 1 4 2\n"),
                   "room.txt:2: obstacle 0: needs at least 3 vertices (got 2)");
  ExpectInputError(parse("# a bow tie\nwalkable 0 0 4 4 4 0 0 3\nexit 4 1 4 2\n"),
                   "room.txt:2: walkable: edges 0 and 2 cross");
  ExpectInputError(parse("walkable 0 0 1 1 2 2\nexit 0 0 1 1\n"),
                   "room.txt:1: walkable: has zero area");
  ExpectInputError(parse("walkable 0 0 4 0 4 4 0 4\n\nexit 2 2 3 2\n"),
                   "room.txt:3: exit 0: not on an edge of the walkable polygon");
  ExpectInputError(parse("walkable 0 0 4 0 4 4 0 4\nexit 4 1 4 3\nexit 4 2 4 3.5\n"),
                   "room.txt:3: exit 1: overlaps exit 0");
  ExpectInputError(parse("walkable 0 0 4 0 4 4 0 4\nobstacle 3 1 5 1 5 2\nexit 4 3 4 3.5\n"),
                   "room.txt:2: obstacle 0: not inside the walkable polygon");
  ExpectInputError(parse("walkable 0 0 4 0 4 4 0 4\n"), "room.txt: exit: the geometry needs");
  ExpectInputError(parse("walkable 0 0 4 0 4\n"), "room.txt:1: expected an even number");
  ExpectInputError(parse("wall 0 0 4 0\n"), "room.txt:1: unknown keyword 'wall'");
  ExpectInputError(parse("exit 0 0 4 0 1 1\n"), "room.txt:1: an exit is a segment");
  ExpectInputError(parse("obstacle 0 0 1 0 1 1\n"), "room.txt: no walkable polygon");
  ExpectInputError(parse("walkable 0 0 4 0 4 4\nwalkable 0 0 4 0 4 4\n"),
                   "room.txt:2: a second walkable polygon");
  ExpectInputError([] { (void)ReadCrowdGeometry("/nonexistent/room.txt", "room.txt"); },
                   "room.txt: cannot be read");
}

// People out through either exit: counted once, at the exit nearest to them.
TEST(CrowdGeometry, EvacuationCountsEachExit) {
  const CrowdGeometry g = ParseCrowdGeometry(kTwoExits, "room.txt");
  EvacuationCount count(g, 3);
  EXPECT_EQ(count.exits(), 2u);
  EXPECT_EQ(count.Update(std::vector<double>{5.0, 1.0, 9.0, 3.0, 1.0, 1.5}), 0);
  EXPECT_EQ(count.Update(std::vector<double>{5.0, 1.0, 10.2, 3.0, -0.1, 1.5}), 2);
  EXPECT_EQ(count.Update(std::vector<double>{5.0, 1.0, 9.9, 3.0, -0.3, 1.5}), 2);  // stays out
  EXPECT_EQ(count.OutPerExit(), (std::vector<int>{1, 1}));
  EXPECT_EQ(count.OutIds(), (std::vector<int>{1, 2}));
  EXPECT_EQ(count.OutExits(), (std::vector<int>{0, 1}));
  EvacuationCount restored(g, 3);
  restored.RestoreOut(count.OutIds(), count.OutExits());
  EXPECT_EQ(restored.OutPerExit(), count.OutPerExit());
  ExpectInputError([&] { restored.RestoreOut(std::vector<int>{0}, std::vector<int>{2}); },
                   "exit 2 of evacuated id 0 is out of range");
}

// The count on 2 threads (the inside tests split between them) against 1: the same totals, ids
// and exits after each call, for 10^4 people in shuffled slots crossing both exits over a few
// calls. It fails if a parallel pass counts a person twice or skips one.
TEST(CrowdGeometry, EvacuationCountIsTheSameOnTwoThreads) {
  const CrowdGeometry g = ParseCrowdGeometry(kTwoExits, "room.txt");
  constexpr int kPeople = 10000;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-0.5, 10.5), y(0.0, 4.0);
  std::vector<int> ids(kPeople);
  for (int i = 0; i < kPeople; ++i) ids[static_cast<std::size_t>(i)] = i;
  std::shuffle(ids.begin(), ids.end(), rng);
  EvacuationCount one(g, kPeople), two(g, kPeople);
  for (int call = 0; call < 3; ++call) {
    std::vector<double> positions(2 * kPeople);
    for (std::size_t i = 0; i < positions.size(); i += 2) {
      positions[i] = x(rng);
      positions[i + 1] = y(rng);
    }
    const int out = one.Update(ids, positions, 1);
    EXPECT_EQ(two.Update(ids, positions, 2), out);
    EXPECT_GT(out, 0);
    EXPECT_LT(out, kPeople);
    EXPECT_EQ(two.OutIds(), one.OutIds());
    EXPECT_EQ(two.OutExits(), one.OutExits());
    EXPECT_EQ(two.OutPerExit(), one.OutPerExit());
  }
  EXPECT_GT(one.OutPerExit()[0], 0);
  EXPECT_GT(one.OutPerExit()[1], 0);
}

// A room with a passage: its two walls follow the door's edges, and people count at its end.
// PolygonStrips::Contains against the test over every edge on polygons of many vertices: a
// star (every edge short), a rectangle whose sides are cut into collinear pieces (level edges),
// a comb whose teeth span the whole height (so many edge entries that the strips are halved);
// at random points, at every vertex, at edge midpoints and at the vertices' heights.
TEST(PolygonStrips, AnswersAsTheTestOverEveryEdge) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Polygon2> polygons(3);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 600; ++i) {
    const double angle = 2.0 * pi * i / 600, r = 3.0 + 7.0 * unit(rng);
    polygons[0].push_back({r * std::cos(angle), r * std::sin(angle)});
  }
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i < 100; ++i) {
      const double t = i / 100.0;
      const Point2 corners[4] = {{0, 0}, {40, 0}, {40, 30}, {0, 30}};
      const Point2& a = corners[side];
      const Point2& b = corners[(side + 1) % 4];
      polygons[1].push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  for (int i = 0; i < 1500; ++i) {  // teeth of width 1, gaps of 1, 100 high
    polygons[2].push_back({2.0 * i, 0.0});
    polygons[2].push_back({2.0 * i, 100.0});
    polygons[2].push_back({2.0 * i + 1.0, 100.0});
    polygons[2].push_back({2.0 * i + 1.0, 0.0});
  }
  polygons[2].push_back({3000.0, -1.0});
  polygons[2].push_back({0.0, -1.0});
  for (const Polygon2& polygon : polygons) {
    CrowdGeometry g;
    g.walkable = polygon;
    const PolygonStrips strips(polygon);
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const Point2& v : polygon) {
      for (int a = 0; a < 2; ++a) {
        lo[a] = std::min(lo[a], v[a]);
        hi[a] = std::max(hi[a], v[a]);
      }
    }
    std::vector<Point2> points;
    for (int k = 0; k < 20000; ++k) {
      points.push_back({lo[0] - 1 + (hi[0] - lo[0] + 2) * unit(rng),
                        lo[1] - 1 + (hi[1] - lo[1] + 2) * unit(rng)});
    }
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Point2& a = polygon[i];
      const Point2& b = polygon[(i + 1) % polygon.size()];
      points.push_back(a);
      points.push_back({0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])});
      points.push_back({lo[0] + (hi[0] - lo[0]) * unit(rng), a[1]});
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (const Point2& p : {Point2{nan, 0.0}, Point2{0.0, nan}, Point2{-inf, 1.0}, Point2{1.0, inf},
                            Point2{hi[0], hi[1]}, Point2{lo[0], lo[1]}}) {
      points.push_back(p);
    }
    int inside = 0;
    for (const Point2& p : points) {
      ASSERT_EQ(strips.Contains(p[0], p[1]), g.InsideWalkablePolygon(p[0], p[1]))
          << "polygon of " << polygon.size() << " vertices at (" << p[0] << ", " << p[1] << ")";
      inside += g.InsideWalkablePolygon(p[0], p[1]) ? 1 : 0;
    }
    EXPECT_GT(inside, 1000);  // the points test both answers
    EXPECT_LT(inside, static_cast<int>(points.size()) - 1000);
  }
  EXPECT_FALSE(PolygonStrips().Contains(0.0, 0.0));
}

TEST(CrowdGeometry, RoomPassageWallsAndCountLine) {
  Room room;
  room.door_length = 2.0;
  const std::vector<SegmentObstacle> walls = room.Walls();
  ASSERT_EQ(walls.size(), 7u);
  EXPECT_EQ(walls[5].a, (std::array<double, 2>{15.0, room.door_lo()}));
  EXPECT_EQ(walls[6].b, (std::array<double, 2>{17.0, room.door_hi()}));
  EXPECT_EQ(Room().Walls().size(), 5u);
  EvacuationCount count(room, 1);
  EXPECT_EQ(count.Update(std::vector<double>{16.0, 7.5}), 0);
  EXPECT_EQ(count.Update(std::vector<double>{17.1, 7.5}), 1);
  room.door_length = -1.0;
  ExpectInputError([&] { room.Validate(); }, "door_length");
}

}  // namespace
}  // namespace moreau::particles
