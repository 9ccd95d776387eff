#include "run/scene_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace moreau::cli {
namespace {

using Point = std::array<double, 3>;
enum Kind { kWall = 0, kSegment = 1, kSphere = 2, kDoor = 3 };

double Dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point Cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Point Unit(const Point& a) {
  const double n = std::sqrt(Dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}
Point Along(const Point& p, double t, const Point& d) {
  return {p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]};
}

// The axis-aligned box the walls are drawn in (the first k axes; the others stay 0).
struct Box {
  Point lo{0, 0, 0}, hi{0, 0, 0};
  int k = 2;
  void Include(const Point& p, double r = 0.0) {
    for (int a = 0; a < k; ++a) {
      lo[a] = std::min(lo[a], p[a] - r);
      hi[a] = std::max(hi[a], p[a] + r);
    }
  }
  Point Centre() const {
    return {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  }
};

// The point of wall w's boundary nearest p, and its unit normal (first k components).
Point Nearest(const particles::Wall& w, const Point& p, int k, Point* normal) {
  Point n{0, 0, 0};
  for (int a = 0; a < k; ++a) n[a] = w.normal[a];
  const double norm = std::sqrt(Dot(n, n));
  *normal = Unit(n);
  return Along(p, w.offset / norm - Dot(*normal, p), *normal);
}

Box SceneBox(const particles::ParticleModel& model, const ParticleScenario& s) {
  const int k = model.dimension;
  Box box{s.domain_lo, s.domain_hi, k};
  for (int a = k; a < 3; ++a) box.lo[a] = box.hi[a] = 0.0;
  if (s.initial_lo) box.Include(*s.initial_lo);
  if (s.initial_hi) box.Include(*s.initial_hi);
  for (const auto& o : model.spheres) box.Include(o.center, o.radius);
  for (const auto& g : model.segments) {
    box.Include({g.a[0], g.a[1], 0.0});
    box.Include({g.b[0], g.b[1], 0.0});
  }
  const Point centre = box.Centre();
  Point normal;
  for (const auto& w : model.walls) box.Include(Nearest(w, centre, k, &normal));
  double diagonal = 0.0;
  for (int a = 0; a < k; ++a) diagonal += (box.hi[a] - box.lo[a]) * (box.hi[a] - box.lo[a]);
  const double pad = 0.05 * (diagonal > 0.0 ? std::sqrt(diagonal) : 1.0);
  for (int a = 0; a < k; ++a) box.lo[a] -= pad, box.hi[a] += pad;
  return box;
}

// 2D: the wall's line clipped to the box (the nearest point to the centre lies inside it).
std::vector<Point> WallLine(const Point& q, const Point& n, const Box& box) {
  const Point d{-n[1], n[0], 0.0};
  double t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(d[a]) < 1e-300) continue;
    const double ta = (box.lo[a] - q[a]) / d[a], tb = (box.hi[a] - q[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return {Along(q, t0, d), Along(q, t1, d)};
}

// 3D: the polygon where the wall's plane crosses the box's 12 edges, in order around it.
std::vector<Point> WallPolygon(const Point& q, const Point& n, const Box& box) {
  std::vector<Point> points;
  for (int axis = 0; axis < 3; ++axis) {
    for (int corner = 0; corner < 4; ++corner) {
      Point a = box.lo, b;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      a[u] = (corner & 1) != 0 ? box.hi[u] : box.lo[u];
      a[v] = (corner & 2) != 0 ? box.hi[v] : box.lo[v];
      b = a;
      b[axis] = box.hi[axis];
      const double sa = Dot(n, a) - Dot(n, q), sb = Dot(n, b) - Dot(n, q);
      if ((sa < 0.0) == (sb < 0.0) || sa == sb) continue;
      points.push_back(Along(a, sa / (sa - sb), {b[0] - a[0], b[1] - a[1], b[2] - a[2]}));
    }
  }
  const int e = std::abs(n[0]) <= std::abs(n[1]) && std::abs(n[0]) <= std::abs(n[2]) ? 0
                : std::abs(n[1]) <= std::abs(n[2])                                   ? 1
                                                                                     : 2;
  Point axis_e{0, 0, 0};
  axis_e[e] = 1.0;
  const Point u = Unit(Cross(n, axis_e)), v = Cross(n, u);
  std::sort(points.begin(), points.end(), [&](const Point& a, const Point& b) {
    const Point da{a[0] - q[0], a[1] - q[1], a[2] - q[2]},
        db{b[0] - q[0], b[1] - q[1], b[2] - q[2]};
    return std::atan2(Dot(da, v), Dot(da, u)) < std::atan2(Dot(db, v), Dot(db, u));
  });
  return points;
}

void AddSphere(const particles::SphereObstacle& o, int k, std::int64_t index,
               io::SceneGeometry* g) {
  const double pi = std::numbers::pi;
  auto at = [&](double theta, double phi) {
    return Point{o.center[0] + o.radius * std::sin(theta) * std::cos(phi),
                 o.center[1] + o.radius * std::sin(theta) * std::sin(phi),
                 o.center[2] + o.radius * std::cos(theta)};
  };
  if (k == 2) {
    io::GeometryCell cell{{}, kSphere, index};
    for (int j = 0; j < 64; ++j) {
      const Point p = at(pi / 2, 2 * pi * j / 64);
      cell.points.push_back({p[0], p[1], 0.0});
    }
    g->cells.push_back(std::move(cell));
    return;
  }
  constexpr int kLat = 12, kLon = 24;
  for (int i = 0; i < kLat; ++i) {
    for (int j = 0; j < kLon; ++j) {
      const double t0 = pi * i / kLat, t1 = pi * (i + 1) / kLat;
      const double p0 = 2 * pi * j / kLon, p1 = 2 * pi * (j + 1) / kLon;
      io::GeometryCell cell{{at(t0, p0), at(t1, p0)}, kSphere, index};
      if (i + 1 < kLat) cell.points.push_back(at(t1, p1));  // not at the south pole
      if (i > 0) cell.points.push_back(at(t0, p1));         // not at the north pole
      g->cells.push_back(std::move(cell));
    }
  }
}

}  // namespace

io::SceneGeometry SceneOf(const particles::ParticleModel& model,
                          const std::optional<particles::Room>& room,
                          const ParticleScenario& scenario) {
  io::SceneGeometry g{{"wall", "segment", "sphere", "door"}, {}};
  const int k = model.dimension;
  const Box box = SceneBox(model, scenario);
  for (std::size_t w = 0; w < model.walls.size(); ++w) {
    Point n;
    const Point q = Nearest(model.walls[w], box.Centre(), k, &n);
    g.cells.push_back({k == 2 ? WallLine(q, n, box) : WallPolygon(q, n, box), kWall,
                       static_cast<std::int64_t>(w)});
  }
  for (std::size_t s = 0; s < model.segments.size(); ++s) {
    const auto& seg = model.segments[s];
    g.cells.push_back({{{seg.a[0], seg.a[1], 0.0}, {seg.b[0], seg.b[1], 0.0}},
                       kSegment,
                       static_cast<std::int64_t>(s)});
  }
  for (std::size_t s = 0; s < model.spheres.size(); ++s) {
    AddSphere(model.spheres[s], k, static_cast<std::int64_t>(s), &g);
  }
  if (room) {
    g.cells.push_back(
        {{{room->width, room->door_lo(), 0.0}, {room->width, room->door_hi(), 0.0}}, kDoor, 0});
  }
  if (scenario.geometry) {
    const auto& exits = scenario.geometry->exits;
    for (std::size_t e = 0; e < exits.size(); ++e) {
      g.cells.push_back({{{exits[e].a[0], exits[e].a[1], 0.0}, {exits[e].b[0], exits[e].b[1], 0.0}},
                         kDoor,
                         static_cast<std::int64_t>(e)});
    }
  }
  return g;
}

bool WriteSceneGeometry(const particles::ParticleModel& model, const ParticleScenario& scenario,
                        OutputDir& out) {
  const bool any = !model.walls.empty() || !model.segments.empty() || !model.spheres.empty();
  if (!any || !(scenario.output.hdf5 || scenario.output.vtu)) return false;
  io::WriteGeometryVtp(out.Stage("geometry.vtp"), SceneOf(model, scenario.room, scenario));
  return true;
}

}  // namespace moreau::cli
