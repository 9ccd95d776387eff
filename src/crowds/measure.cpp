// Densities, speeds and line crossings (include/moreau/crowds/measure.h).
#include "moreau/crowds/measure.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::crowds {
namespace {

double AreaOf(std::span<const Point> area) {
  const double a = PolygonArea(area);
  if (!(a > 0.0) || !std::isfinite(a)) {
    throw InputError("area", "must be a polygon of positive area");
  }
  return a;
}

// The bounding box of a polygon: lo, hi.
std::array<Point, 2> BoundingBox(std::span<const Point> polygon) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Point lo{kInf, kInf};
  Point hi{-kInf, -kInf};
  for (const Point& p : polygon) {
    for (std::size_t a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  return {lo, hi};
}

bool BoxesOverlap(const std::array<Point, 2>& u, const std::array<Point, 2>& v) {
  return u[0][0] <= v[1][0] && v[0][0] <= u[1][0] && u[0][1] <= v[1][1] && v[0][1] <= u[1][1];
}

// Signed distance of p ahead of the line along its walking direction (unnormalised).
double Ahead(const MeasurementLine& line, Point p) {
  const double ex = line.b[0] - line.a[0];
  const double ey = line.b[1] - line.a[1];
  return (p[0] - line.a[0]) * ey - (p[1] - line.a[1]) * ex;
}

}  // namespace

double ClassicDensity(std::span<const Point> points, std::span<const Point> area) {
  const double a = AreaOf(area);
  const auto inside = std::count_if(points.begin(), points.end(),
                                    [&](const Point& p) { return Contains(area, p); });
  return static_cast<double>(inside) / a;
}

AreaMeasurement MeasureArea(std::span<const Point> points, std::span<const Polygon> cells,
                            std::span<const double> speeds, std::span<const Point> area) {
  const double a = AreaOf(area);
  if (cells.size() != points.size() || (!speeds.empty() && speeds.size() != points.size())) {
    throw InputError(fmt::format("{} points, {} cells and {} speeds: the sizes must agree",
                                 points.size(), cells.size(), speeds.size()));
  }
  AreaMeasurement m;
  for (const Point& p : points) m.count += Contains(area, p) ? 1 : 0;
  m.density_classic = m.count / a;
  const auto area_box = BoundingBox(area);
  double density_sum = 0.0;
  double speed_sum = 0.0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double cell_area = PolygonArea(cells[i]);
    if (!(cell_area > 0.0) || !BoxesOverlap(area_box, BoundingBox(cells[i]))) continue;
    const double shared = PolygonArea(ClipByConvex(area, cells[i]));
    density_sum += shared / cell_area;
    if (!speeds.empty()) speed_sum += speeds[i] * shared;
  }
  m.density_voronoi = density_sum / a;
  m.speed_voronoi = speed_sum / a;
  return m;
}

std::vector<Point> TrackVelocities(std::span<const double> times, std::span<const Point> x) {
  const std::size_t n = times.size();
  if (x.size() != n) {
    throw InputError(fmt::format("{} times and {} positions: the sizes must agree", n, x.size()));
  }
  for (std::size_t k = 1; k < n; ++k) {
    if (!(times[k] > times[k - 1])) throw InputError("times must increase");
  }
  std::vector<Point> v(n, Point{0.0, 0.0});
  for (std::size_t k = 0; k < n && n > 1; ++k) {
    const std::size_t lo = k == 0 ? 0 : k - 1;
    const std::size_t hi = k + 1 == n ? k : k + 1;
    const double dt = times[hi] - times[lo];
    v[k] = {(x[hi][0] - x[lo][0]) / dt, (x[hi][1] - x[lo][1]) / dt};
  }
  return v;
}

double MeasurementLine::length() const { return std::hypot(b[0] - a[0], b[1] - a[1]); }

Point MeasurementLine::direction() const {
  const double w = length();
  return {(b[1] - a[1]) / w, (a[0] - b[0]) / w};
}

std::optional<double> CrossingFraction(const MeasurementLine& line, Point p, Point q) {
  const double fp = Ahead(line, p);
  const double fq = Ahead(line, q);
  if (!(fp <= 0.0 && fq > 0.0)) return std::nullopt;
  const double s = fp / (fp - fq);  // in [0, 1)
  const Point c{p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])};
  const double ex = line.b[0] - line.a[0];
  const double ey = line.b[1] - line.a[1];
  const double u = ((c[0] - line.a[0]) * ex + (c[1] - line.a[1]) * ey) / (ex * ex + ey * ey);
  if (u < 0.0 || u > 1.0) return std::nullopt;
  return s;
}

std::optional<double> FirstCrossingTime(const MeasurementLine& line, std::span<const double> times,
                                        std::span<const Point> x) {
  if (x.size() != times.size()) {
    throw InputError(
        fmt::format("{} times and {} positions: the sizes must agree", times.size(), x.size()));
  }
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    if (const auto s = CrossingFraction(line, x[k], x[k + 1])) {
      return times[k] + *s * (times[k + 1] - times[k]);
    }
  }
  return std::nullopt;
}

LineFlow FlowThroughLine(std::span<const double> crossing_times, double line_length) {
  LineFlow f;
  f.crossings = static_cast<int>(crossing_times.size());
  if (crossing_times.empty()) return f;
  const auto [lo, hi] = std::minmax_element(crossing_times.begin(), crossing_times.end());
  f.first = *lo;
  f.last = *hi;
  if (f.crossings >= 2 && f.last > f.first) {
    f.flow = (f.crossings - 1) / (f.last - f.first);
    f.specific_flow = line_length > 0.0 ? f.flow / line_length : 0.0;
  }
  return f;
}

double FlowInWindow(std::span<const double> crossing_times, double t0, double t1) {
  if (!(t1 > t0)) throw InputError(fmt::format("the window [{}, {}) is empty", t0, t1));
  const auto n = std::count_if(crossing_times.begin(), crossing_times.end(),
                               [&](double t) { return t >= t0 && t < t1; });
  return static_cast<double>(n) / (t1 - t0);
}

}  // namespace moreau::crowds
