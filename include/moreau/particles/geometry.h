// A crowd's walkable area in the plane (dimension 2): one walkable polygon, polygonal holes in it
// (obstacles: pillars) and exits (segments on the walkable polygon's boundary), read from a
// plain-text file or built in code. Its edges become the engine's segment walls (particles stay
// at distance ≥ r_i from them), and routing.h computes the walking distance to the nearest exit
// over it. Lengths in the scenario's unit (metres).
//
// The text format (docs/crowds.md "Geometry and routing"), one item per line:
//   walkable x0 y0 x1 y1 x2 y2 …   the walkable polygon (exactly one; ≥ 3 vertices)
//   obstacle x0 y0 x1 y1 x2 y2 …   a hole in it (any number; ≥ 3 vertices)
//   exit x0 y0 x1 y1               an exit segment, lying on one edge of the walkable polygon
// Polygons are closed implicitly (the last vertex joins the first), in either orientation. A
// `#` starts a comment; blank lines are skipped. Numbers are finite decimals.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "moreau/particles/model.h"

namespace moreau::particles {

using Point2 = std::array<double, 2>;
using Polygon2 = std::vector<Point2>;

struct CrowdExit {
  Point2 a{0.0, 0.0};
  Point2 b{0.0, 0.0};
};

struct CrowdGeometry {
  Polygon2 walkable;
  std::vector<Polygon2> obstacles;
  std::vector<CrowdExit> exits;

  // Throws InputError(reason) naming the item ("walkable: needs at least 3 vertices (got 2)",
  // "obstacle 1: edges 0 and 2 cross", "exit 0: not on an edge of the walkable polygon",
  // "obstacle 0: not inside the walkable polygon"). Checks: finite coordinates, 3 to 5000
  // vertices a polygon (20000 in all), non-zero area, no two edges of a polygon crossing (O(n²)
  // per polygon), obstacles inside the walkable polygon and apart from its boundary and each
  // other, 1 to 1000 exits, each of non-zero length and on one edge of the walkable polygon
  // (within 1e−9 of the edge's length), exits not overlapping.
  void Validate() const;

  // The walls: the walkable polygon's edges without the exits, then every obstacle's edges.
  std::vector<SegmentObstacle> Walls() const;
  // Whether (x, y) lies inside the walkable polygon and outside every obstacle (even-odd rule;
  // points on an edge count either way).
  bool Walkable(double x, double y) const;
  bool InsideWalkablePolygon(double x, double y) const;
  // The unit normal of exit k pointing out of the walkable polygon.
  Point2 ExitNormal(std::size_t k) const;
  // The exit nearest to (x, y) (Euclidean distance to its segment; the lower index on a tie).
  std::size_t NearestExit(double x, double y) const;
  // Whether the axis-aligned box [lo, hi] lies in the walkable area: its corners walkable and
  // no wall crossing it.
  bool BoxWalkable(const Point2& lo, const Point2& hi) const;
};

// The even-odd test of one polygon (CrowdGeometry::InsideWalkablePolygon's) with its edges
// binned by horizontal strips: a point looks only at the edges whose height range meets its
// strip, by the same operations per edge, and gets the answer of the test over every edge (an
// edge outside the strip cannot cross the point's horizontal line). For the tests of every
// person at every step, where a floor plan of many vertices would make each one slow.
class PolygonStrips {
 public:
  PolygonStrips() = default;
  explicit PolygonStrips(const Polygon2& polygon);
  // Whether (x, y) is inside: InsidePolygon(polygon, x, y) bit for bit, NaN included.
  bool Contains(double x, double y) const;

 private:
  struct Edge {
    Point2 a, b;
  };
  int Strip(double y) const;

  double y0_ = 0.0, y1_ = -1.0, height_ = 1.0;  // the strips cover [y0, y1]
  int strips_ = 0;
  std::vector<int> begin_;   // strip s: edges_[begin_[s], begin_[s + 1])
  std::vector<Edge> edges_;  // each strip's edges, an edge in every strip its heights meet
};

// Reads the text format above; `name` (the file's path as the user wrote it) starts every
// error: InputError "NAME:LINE: REASON" ("room.txt:3: expected an even number of coordinates",
// "room.txt:7: nan is not a finite number", "room.txt:2: obstacle 0: needs at least 3 vertices
// (got 2)"), or "NAME: REASON" for what no line holds ("room.txt: no walkable polygon"). The
// result is validated.
CrowdGeometry ParseCrowdGeometry(std::string_view text, std::string_view name);

// The same from the file at `path` (InputError "NAME: cannot be read" when it cannot be opened,
// "NAME: not a regular file" for a folder, a FIFO or a device, and a file over 16 MiB).
CrowdGeometry ReadCrowdGeometry(const std::string& path, std::string_view name);

// Distance from p to the segment [a, b].
double DistanceToSegment(const Point2& p, const Point2& a, const Point2& b);

}  // namespace moreau::particles
