// The crowd measurements (include/moreau/crowds/measure.h) against exact answers: Voronoi cells of
// square and hexagonal lattices, the cells tiling their bound, classic densities by counting, and
// line crossings of walkers at known times.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/crowds/measure.h"

namespace moreau::crowds {
namespace {

void ExpectMeasureInputError(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one mentioning '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// An nx × ny square lattice of spacing a, the first point at `origin`.
std::vector<Point> SquareLattice(int nx, int ny, double a, Point origin) {
  std::vector<Point> p;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) p.push_back({origin[0] + i * a, origin[1] + j * a});
  }
  return p;
}

TEST(CrowdPolygons, AreaContainmentAndClipping) {
  const Polygon square = Rectangle({0.0, 0.0}, {2.0, 3.0});
  EXPECT_EQ(PolygonArea(square), 6.0);
  Polygon clockwise(square.rbegin(), square.rend());
  EXPECT_EQ(PolygonArea(clockwise), 6.0);
  EXPECT_TRUE(IsConvex(square));
  EXPECT_TRUE(IsConvex(clockwise));
  EXPECT_FALSE(IsConvex(Polygon{{0, 0}, {2, 0}, {1, 0.5}, {2, 2}, {0, 2}}));
  EXPECT_TRUE(Contains(square, {1.0, 1.0}));
  EXPECT_FALSE(Contains(square, {2.5, 1.0}));
  // x ≤ 1 keeps half; the triangle x + y ≤ 2 inside [0, 2] × [0, 3] has area 2.
  EXPECT_DOUBLE_EQ(PolygonArea(ClipByHalfPlane(square, {1.0, 0.0}, 1.0)), 3.0);
  EXPECT_DOUBLE_EQ(PolygonArea(ClipByHalfPlane(square, {1.0, 1.0}, 2.0)), 2.0);
  EXPECT_TRUE(ClipByHalfPlane(square, {1.0, 0.0}, -1.0).empty());
  // An L-shaped (non-convex) subject clipped by a convex square: the exact overlap.
  const Polygon ell{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
  EXPECT_DOUBLE_EQ(PolygonArea(ell), 5.0);
  EXPECT_DOUBLE_EQ(PolygonArea(ClipByConvex(ell, Rectangle({0.5, 0.5}, {2.5, 2.5}))),
                   0.5 * 2.0 + 0.5 * 1.5);
  // A regular polygon of n vertices on the unit circle: (n/2) sin(2π/n).
  EXPECT_NEAR(PolygonArea(RegularPolygon({1.0, 2.0}, 1.0, 12)),
              6.0 * std::sin(2.0 * std::numbers::pi / 12.0), 1e-14);
}

TEST(CrowdVoronoi, SquareLatticeGivesOneOverASquaredInAnInteriorArea) {
  for (const double a : {0.5, 0.7, 1.3}) {
    const auto points = SquareLattice(9, 7, a, {0.25, -0.5});
    VoronoiOptions options;
    options.bound = Rectangle({-1.0, -2.0}, {0.25 + 10 * a, 8 * a});
    const auto cells = VoronoiCells(points, options);
    // Interior cells are squares of area a² centred on their points.
    const std::size_t interior = 3 * 9 + 4;
    EXPECT_NEAR(PolygonArea(cells[interior]), a * a, 1e-12 * a * a);
    // An area well inside the lattice, cut through cells at odd places.
    const Polygon area = Rectangle({0.25 + 2.3 * a, -0.5 + 1.7 * a}, {0.25 + 5.9 * a, 4.2 * a});
    const std::vector<double> speeds(points.size(), 1.25);
    const AreaMeasurement m = MeasureArea(points, cells, speeds, area);
    EXPECT_NEAR(m.density_voronoi, 1.0 / (a * a), 1e-12 / (a * a)) << a;
    EXPECT_NEAR(m.speed_voronoi, 1.25, 1e-12) << a;  // Σ_i v_i |V_i ∩ A| / |A| = v
  }
}

TEST(CrowdVoronoi, HexagonalLatticeCellsAreRegularHexagons) {
  const double a = 0.8;
  std::vector<Point> points;
  for (int j = 0; j < 9; ++j) {
    for (int i = 0; i < 9; ++i) {
      points.push_back({(i + 0.5 * (j % 2)) * a, j * a * std::sqrt(3.0) / 2.0});
    }
  }
  VoronoiOptions options;
  options.bound = Rectangle({-2.0, -2.0}, {10 * a, 9 * a});
  const auto cells = VoronoiCells(points, options);
  for (const std::size_t c : {std::size_t{4 * 9 + 4}, std::size_t{3 * 9 + 3}}) {
    ASSERT_EQ(cells[c].size(), 6U) << c;
    EXPECT_NEAR(PolygonArea(cells[c]), std::sqrt(3.0) / 2.0 * a * a, 1e-12);
    for (const Point& v : cells[c]) {  // every vertex at the circumradius a/√3
      EXPECT_NEAR(std::hypot(v[0] - points[c][0], v[1] - points[c][1]), a / std::sqrt(3.0), 1e-12);
    }
  }
}

TEST(CrowdVoronoi, ClippedCellsTileTheBound) {
  SplitMix64 rng(20260104);
  std::vector<Point> points(150);
  for (Point& p : points) p = {10.0 * rng.Uniform01(), 6.0 * rng.Uniform01()};
  VoronoiOptions options;
  options.bound = {{-1.0, -1.0}, {11.0, -0.5}, {10.5, 7.0}, {0.0, 6.5}};
  const auto cells = VoronoiCells(points, options);
  double sum = 0.0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    sum += PolygonArea(cells[i]);
    for (std::size_t j = 0; j < points.size(); j += 7) {  // every vertex is nearest to i
      for (const Point& v : cells[i]) {
        EXPECT_LE(std::hypot(v[0] - points[i][0], v[1] - points[i][1]),
                  std::hypot(v[0] - points[j][0], v[1] - points[j][1]) + 1e-9);
      }
    }
  }
  EXPECT_NEAR(sum, PolygonArea(options.bound), 1e-10 * PolygonArea(options.bound));
  // An area inside the bound: Σ |V_i ∩ A| = |A|, so ρ_V |A| ≤ N and v_V = 1 for unit speeds.
  const Polygon area = Rectangle({2.0, 1.0}, {7.0, 5.0});
  const std::vector<double> ones(points.size(), 1.0);
  EXPECT_NEAR(MeasureArea(points, cells, ones, area).speed_voronoi, 1.0, 1e-12);
}

TEST(CrowdVoronoi, CutoffBoundsLonePeople) {
  VoronoiOptions options;
  options.bound = Rectangle({-10.0, -10.0}, {10.0, 10.0});
  options.cutoff_radius = 0.5;
  const std::vector<Point> points{{0.0, 0.0}, {5.0, 5.0}, {5.6, 5.0}};
  const auto cells = VoronoiCells(points, options);
  EXPECT_NEAR(PolygonArea(cells[0]), 6.0 * 0.25 * std::sin(std::numbers::pi / 6.0), 1e-14);
  EXPECT_LT(PolygonArea(cells[1]), PolygonArea(cells[0]));  // cut by the bisector x = 5.3
}

TEST(CrowdVoronoi, BadOptionsAreInputErrors) {
  VoronoiOptions options;
  const std::vector<Point> points{{0.0, 0.0}};
  ExpectMeasureInputError([&] { VoronoiCells(points, options); }, "bound");
  options.bound = {{0, 0}, {2, 0}, {1, 0.5}, {2, 2}, {0, 2}};
  ExpectMeasureInputError([&] { VoronoiCells(points, options); }, "convex");
  options.bound = Rectangle({0.0, 0.0}, {1.0, 1.0});
  options.cutoff_radius = 0.0;
  ExpectMeasureInputError([&] { VoronoiCells(points, options); }, "cutoff_radius: must be > 0");
  options.cutoff_radius = 1.0;
  options.cutoff_vertices = 2;
  ExpectMeasureInputError([&] { VoronoiCells(points, options); }, "cutoff_vertices");
}

TEST(CrowdDensity, ClassicDensityCountsThePeopleInside) {
  const auto points = SquareLattice(10, 10, 1.0, {0.5, 0.5});  // centres of unit squares
  EXPECT_EQ(ClassicDensity(points, Rectangle({2.0, 3.0}, {5.0, 5.0})), 6.0 / 6.0);
  EXPECT_EQ(ClassicDensity(points, Rectangle({0.0, 0.0}, {2.0, 10.0})), 20.0 / 20.0);
  // A triangle holding (0.5, 0.5), (1.5, 0.5), (0.5, 1.5) of the lattice: 3 / 4.5.
  EXPECT_DOUBLE_EQ(ClassicDensity(points, Polygon{{0.0, 0.0}, {3.0, 0.0}, {0.0, 3.0}}), 3.0 / 4.5);
  ExpectMeasureInputError([&] { ClassicDensity(points, Polygon{{0, 0}, {1, 1}}); }, "area");
}

TEST(CrowdSpeed, CentralDifferencesAreExactForUniformMotionAndSecondOrder) {
  std::vector<double> t;
  std::vector<Point> x;
  for (int k = 0; k < 6; ++k) {
    t.push_back(0.5 * k);
    x.push_back({1.0 + 1.2 * t.back(), 2.0 - 0.4 * t.back()});
  }
  for (const Point& v : TrackVelocities(t, x)) {
    EXPECT_NEAR(v[0], 1.2, 1e-14);
    EXPECT_NEAR(v[1], -0.4, 1e-14);
  }
  // x = t²: the central difference at t_k is exactly 2 t_k; one-sided at the ends.
  for (std::size_t k = 0; k < t.size(); ++k) x[k] = {t[k] * t[k], 0.0};
  const auto v = TrackVelocities(t, x);
  for (std::size_t k = 1; k + 1 < t.size(); ++k) EXPECT_NEAR(v[k][0], 2.0 * t[k], 1e-14);
  EXPECT_NEAR(v.front()[0], 0.5, 1e-14);  // (0.25 − 0) / 0.5
  EXPECT_EQ(TrackVelocities(std::vector<double>{1.0}, std::vector<Point>{{3.0, 4.0}})[0][0], 0.0);
  ExpectMeasureInputError([&] { TrackVelocities(std::vector<double>{1.0, 1.0}, x); }, "sizes");
}

TEST(CrowdLine, StraightWalkersCrossAtTheirExactTimes) {
  // A line at x = 4 from y = −1 to y = 3 counts walking toward +x.
  const MeasurementLine line{{4.0, -1.0}, {4.0, 3.0}};
  EXPECT_EQ(line.length(), 4.0);
  EXPECT_EQ(line.direction()[0], 1.0);
  std::vector<double> crossings;
  const double dt = 0.25;
  for (int person = 0; person < 5; ++person) {
    const double v = 0.6 + 0.2 * person;  // m/s
    const double x0 = 0.3 * person;
    const double y = -1.5 + person;  // person 0 passes beside the line (y = −1.5)
    std::vector<double> t;
    std::vector<Point> x;
    for (int k = 0; k <= 40; ++k) {
      t.push_back(k * dt);
      x.push_back({x0 + v * t.back(), y});
    }
    const auto crossed = FirstCrossingTime(line, t, x);
    if (person == 0) {
      EXPECT_FALSE(crossed);
      continue;
    }
    ASSERT_TRUE(crossed) << person;
    EXPECT_NEAR(*crossed, (4.0 - x0) / v, 1e-12) << person;
    crossings.push_back(*crossed);
    // Walking back does not count.
    std::vector<Point> back(x.rbegin(), x.rend());
    EXPECT_FALSE(FirstCrossingTime(line, t, back));
  }
  const LineFlow f = FlowThroughLine(crossings, line.length());
  EXPECT_EQ(f.crossings, 4);
  EXPECT_DOUBLE_EQ(f.first, (4.0 - 0.3 * 4) / 1.4);
  EXPECT_DOUBLE_EQ(f.last, (4.0 - 0.3) / 0.8);
  EXPECT_NEAR(f.flow, 3.0 / (f.last - f.first), 1e-15);
  EXPECT_NEAR(f.specific_flow, f.flow / 4.0, 1e-15);
  EXPECT_EQ(FlowInWindow(crossings, 0.0, 10.0), 0.4);
  ExpectMeasureInputError([&] { FlowInWindow(crossings, 1.0, 1.0); }, "window");
}

TEST(CrowdLine, AStepEndingOnTheLineCrossesOnTheNext) {
  const MeasurementLine line{{0.0, 0.0}, {0.0, 1.0}};
  EXPECT_FALSE(CrossingFraction(line, {-1.0, 0.5}, {0.0, 0.5}));
  EXPECT_EQ(*CrossingFraction(line, {0.0, 0.5}, {1.0, 0.5}), 0.0);
  EXPECT_EQ(*CrossingFraction(line, {-1.0, 0.5}, {3.0, 0.5}), 0.25);
  EXPECT_FALSE(CrossingFraction(line, {-1.0, 1.5}, {1.0, 1.5}));  // beside the segment
}

}  // namespace
}  // namespace moreau::crowds
