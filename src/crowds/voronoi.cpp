// Polygons, clipping and Voronoi cells (include/moreau/crowds/measure.h).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/crowds/measure.h"

namespace moreau::crowds {
namespace {

double SignedArea(std::span<const Point> polygon) {
  const std::size_t m = polygon.size();
  if (m < 3) return 0.0;
  double twice = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const Point& p = polygon[k];
    const Point& q = polygon[(k + 1) % m];
    twice += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * twice;
}

double Dot(Point u, Point v) { return u[0] * v[0] + u[1] * v[1]; }

// The polygon counter-clockwise.
Polygon CounterClockwise(std::span<const Point> polygon) {
  Polygon out(polygon.begin(), polygon.end());
  if (SignedArea(out) < 0.0) std::reverse(out.begin(), out.end());
  return out;
}

// The largest |v| over the polygon's vertices (relative to the person).
double FarthestVertex(const Polygon& cell) {
  double r2 = 0.0;
  for (const Point& v : cell) r2 = std::max(r2, Dot(v, v));
  return std::sqrt(r2);
}

}  // namespace

double PolygonArea(std::span<const Point> polygon) { return std::abs(SignedArea(polygon)); }

bool Contains(std::span<const Point> polygon, Point p) {
  bool inside = false;
  const std::size_t m = polygon.size();
  for (std::size_t k = 0, j = m - 1; k < m; j = k++) {
    const Point& a = polygon[k];
    const Point& b = polygon[j];
    if ((a[1] > p[1]) != (b[1] > p[1])) {
      const double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (p[0] < x) inside = !inside;
    }
  }
  return inside;
}

bool IsConvex(std::span<const Point> polygon) {
  const double area = SignedArea(polygon);
  if (!(std::abs(area) > 0.0) || !std::isfinite(area)) return false;
  const std::size_t m = polygon.size();
  for (std::size_t k = 0; k < m; ++k) {
    const Point& p = polygon[k];
    const Point& q = polygon[(k + 1) % m];
    const Point& r = polygon[(k + 2) % m];
    const double cross = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
    if (cross * area < 0.0) return false;
  }
  return true;
}

Polygon Rectangle(Point lo, Point hi) {
  return {{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
}

Polygon RegularPolygon(Point center, double radius, int vertices) {
  Polygon out(static_cast<std::size_t>(std::max(vertices, 0)));
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double angle =
        2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(vertices);
    out[k] = {center[0] + radius * std::cos(angle), center[1] + radius * std::sin(angle)};
  }
  return out;
}

Polygon ClipByHalfPlane(std::span<const Point> polygon, Point normal, double offset) {
  Polygon out;
  const std::size_t m = polygon.size();
  out.reserve(m + 1);
  for (std::size_t k = 0; k < m; ++k) {
    const Point& p = polygon[k];
    const Point& q = polygon[(k + 1) % m];
    const double fp = Dot(normal, p) - offset;
    const double fq = Dot(normal, q) - offset;
    if (fp <= 0.0) out.push_back(p);
    if ((fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0)) {
      const double s = fp / (fp - fq);
      out.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])});
    }
  }
  if (out.size() < 3) out.clear();
  return out;
}

Polygon ClipByConvex(std::span<const Point> subject, std::span<const Point> convex) {
  const Polygon clip = CounterClockwise(convex);
  Polygon out(subject.begin(), subject.end());
  const std::size_t m = clip.size();
  for (std::size_t k = 0; k < m && !out.empty(); ++k) {
    const Point& c = clip[k];
    const Point& d = clip[(k + 1) % m];
    // Keep the left of c → d: ⟨(e_y, −e_x), p⟩ ≤ ⟨(e_y, −e_x), c⟩.
    const Point normal{d[1] - c[1], c[0] - d[0]};
    out = ClipByHalfPlane(out, normal, Dot(normal, c));
  }
  return out;
}

void VoronoiOptions::Validate() const {
  if (bound.size() < 3 || !IsConvex(bound)) {
    throw InputError("bound", "must be a convex polygon of positive area");
  }
  for (const Point& p : bound) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) {
      throw InputError("bound", "vertices must be finite");
    }
  }
  if (cutoff_radius && !(*cutoff_radius > 0.0 && std::isfinite(*cutoff_radius))) {
    throw InputError("cutoff_radius", fmt::format("must be > 0 (got {})", *cutoff_radius));
  }
  if (cutoff_vertices < 3) {
    throw InputError("cutoff_vertices", fmt::format("must be ≥ 3 (got {})", cutoff_vertices));
  }
}

std::vector<Polygon> VoronoiCells(std::span<const Point> points, const VoronoiOptions& options) {
  options.Validate();
  const Polygon bound = CounterClockwise(options.bound);
  const std::size_t n = points.size();
  std::vector<Polygon> cells(n);
  std::vector<std::size_t> order(n);
  std::vector<double> d2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point xi = points[i];
    // The cell in coordinates relative to x_i (the bisectors' offsets stay small).
    Polygon cell;
    cell.reserve(bound.size());
    for (const Point& v : bound) cell.push_back({v[0] - xi[0], v[1] - xi[1]});
    if (options.cutoff_radius) {
      cell = ClipByConvex(
          cell, RegularPolygon({0.0, 0.0}, *options.cutoff_radius, options.cutoff_vertices));
    }
    for (std::size_t j = 0; j < n; ++j) {
      const Point d{points[j][0] - xi[0], points[j][1] - xi[1]};
      d2[j] = Dot(d, d);
    }
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return d2[a] < d2[b] || (d2[a] == d2[b] && a < b);
    });
    double reach = FarthestVertex(cell);
    for (const std::size_t j : order) {
      if (cell.empty()) break;
      if (d2[j] == 0.0) continue;  // itself, or someone at the same position
      if (std::sqrt(d2[j]) >= 2.0 * reach) break;
      const Point d{points[j][0] - xi[0], points[j][1] - xi[1]};
      cell = ClipByHalfPlane(cell, d, 0.5 * d2[j]);  // ⟨p, d⟩ ≤ |d|²/2: nearer to x_i
      reach = FarthestVertex(cell);
    }
    for (Point& v : cell) v = {v[0] + xi[0], v[1] + xi[1]};
    cells[i] = std::move(cell);
  }
  return cells;
}

}  // namespace moreau::crowds
