#include "moreau/particles/routing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::particles {

namespace {

constexpr double kNoDistance = std::numeric_limits<double>::infinity();
constexpr double kMaxNodes = 1e7;  // about 26 bytes a node while the field is built

// The first-order upwind update at a node from the smallest known neighbour value per axis
// (a, b; +∞ when none): the root of (u − a)² + (u − b)² = h² when both are close enough, else
// min(a, b) + h.
double EikonalUpdate(double a, double b, double h) {
  if (a > b) std::swap(a, b);
  if (!(b < kNoDistance) || b - a >= h) return a + h;
  return 0.5 * (a + b + std::sqrt(2.0 * h * h - (a - b) * (a - b)));
}

// The unfinished nodes of the march, smallest (distance, node) first: a binary heap of node
// numbers with each node's place in it, so that a node whose distance drops moves up in place
// instead of being pushed again. Its pops are those of a heap of (distance, node) pairs that
// skips the stale ones, in the same order, with one entry per node instead of one per update.
// A popped node is done (its distance known) and is not added again.
class NodeHeap {
 public:
  explicit NodeHeap(const std::vector<double>& d) : d_(d), place_(d.size(), kAbsent) {}

  bool empty() const { return nodes_.empty(); }
  bool done(std::size_t n) const { return place_[n] == kDone; }

  // Adds node n, or moves it up after d[n] dropped.
  void Update(std::uint32_t n) {
    if (place_[n] == kAbsent) {
      place_[n] = static_cast<std::uint32_t>(nodes_.size());
      nodes_.push_back(n);
    }
    Up(place_[n]);
  }

  std::uint32_t Pop() {
    const std::uint32_t top = nodes_.front();
    place_[top] = kDone;
    const std::uint32_t last = nodes_.back();
    nodes_.pop_back();
    if (!nodes_.empty()) {
      Put(last, 0);
      Down(0);
    }
    return top;
  }

 private:
  static constexpr std::uint32_t kAbsent = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::uint32_t kDone = kAbsent - 1;

  bool Before(std::uint32_t a, std::uint32_t b) const {
    return d_[a] < d_[b] || (d_[a] == d_[b] && a < b);
  }
  void Put(std::uint32_t n, std::size_t at) {
    nodes_[at] = n;
    place_[n] = static_cast<std::uint32_t>(at);
  }
  void Up(std::size_t at) {
    const std::uint32_t n = nodes_[at];
    while (at > 0 && Before(n, nodes_[(at - 1) / 2])) {
      Put(nodes_[(at - 1) / 2], at);
      at = (at - 1) / 2;
    }
    Put(n, at);
  }
  void Down(std::size_t at) {
    const std::uint32_t n = nodes_[at];
    for (;;) {
      std::size_t child = 2 * at + 1;
      if (child >= nodes_.size()) break;
      if (child + 1 < nodes_.size() && Before(nodes_[child + 1], nodes_[child])) ++child;
      if (!Before(nodes_[child], n)) break;
      Put(nodes_[child], at);
      at = child;
    }
    Put(n, at);
  }

  const std::vector<double>& d_;
  std::vector<std::uint32_t> place_;
  std::vector<std::uint32_t> nodes_;
};

}  // namespace

const FieldList<RoutingOptions>& RoutingOptions::Fields() {
  static const FieldList<RoutingOptions> list = [] {
    FieldList<RoutingOptions> t;
    t.Number("spacing", &RoutingOptions::spacing, Range::Positive(), "length",
             "grid spacing of the distance field")
        .Number("clearance", &RoutingOptions::clearance, Range::NonNegative(), "length",
                "distance the routes keep from the walls");
    return t;
  }();
  return list;
}

void RoutingOptions::Validate() const { Fields().Validate(*this); }

DistanceField::DistanceField(const CrowdGeometry& geometry, const RoutingOptions& options)
    : geometry_(geometry), h_(options.spacing) {
  options.Validate();
  geometry_.Validate();
  double lo[2] = {kNoDistance, kNoDistance}, hi[2] = {-kNoDistance, -kNoDistance};
  for (const Point2& p : geometry_.walkable) {
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], p[static_cast<std::size_t>(a)]);
      hi[a] = std::max(hi[a], p[static_cast<std::size_t>(a)]);
    }
  }
  const double cells =
      std::ceil((hi[0] - lo[0]) / h_ + 3.0) * std::ceil((hi[1] - lo[1]) / h_ + 3.0);
  if (!(cells <= kMaxNodes)) {
    throw InputError("spacing", fmt::format("the grid would have {:.3g} nodes (more than {:.0e})",
                                            cells, kMaxNodes));
  }
  x0_ = lo[0] - h_;
  y0_ = lo[1] - h_;
  nx_ = static_cast<int>(std::ceil((hi[0] - lo[0]) / h_)) + 3;
  ny_ = static_cast<int>(std::ceil((hi[1] - lo[1]) / h_)) + 3;
  for (std::size_t k = 0; k < geometry_.exits.size(); ++k) {
    exit_normal_.push_back(geometry_.ExitNormal(k));
  }
  walkable_ = PolygonStrips(geometry_.walkable);
  const std::vector<char> free = FreeNodes(options.clearance);
  March(free);
  NodeDirections();
}

std::vector<char> DistanceField::FreeNodes(double clearance) const {
  std::vector<char> free(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), 0);
  // Row by row, the even-odd rule over every polygon's edges (CrowdGeometry::Walkable's test):
  // a node is in the walkable area when an odd number of crossings lie to its right.
  std::vector<const Polygon2*> polygons = {&geometry_.walkable};
  for (const Polygon2& p : geometry_.obstacles) polygons.push_back(&p);
  std::vector<double> crossings;
  for (int j = 0; j < ny_; ++j) {
    const double y = y0_ + j * h_;
    crossings.clear();
    for (const Polygon2* p : polygons) {
      for (std::size_t v = 0, u = p->size() - 1; v < p->size(); u = v++) {
        const Point2& a = (*p)[v];
        const Point2& b = (*p)[u];
        if ((a[1] > y) != (b[1] > y)) {
          crossings.push_back((b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]);
        }
      }
    }
    std::sort(crossings.begin(), crossings.end());
    std::size_t right = 0;  // crossings at or left of the node
    for (int i = 0; i < nx_; ++i) {
      const double x = x0_ + i * h_;
      while (right < crossings.size() && !(x < crossings[right])) ++right;
      free[Index(i, j)] = (crossings.size() - right) % 2 == 1 ? 1 : 0;
    }
  }
  // The walls inflated by the clearance: the nodes of each wall's box closer than it.
  for (const SegmentObstacle& w : geometry_.Walls()) {
    const Point2 a{w.a[0], w.a[1]}, b{w.b[0], w.b[1]};
    const auto node = [&](double v, double origin, int n) {
      return std::clamp(static_cast<int>(std::floor((v - origin) / h_)), 0, n - 1);
    };
    const int i0 = node(std::min(a[0], b[0]) - clearance, x0_, nx_);
    const int i1 = node(std::max(a[0], b[0]) + clearance, x0_, nx_) + 1;
    const int j0 = node(std::min(a[1], b[1]) - clearance, y0_, ny_);
    const int j1 = node(std::max(a[1], b[1]) + clearance, y0_, ny_) + 1;
    for (int j = j0; j <= std::min(j1, ny_ - 1); ++j) {
      for (int i = i0; i <= std::min(i1, nx_ - 1); ++i) {
        if (DistanceToSegment({x0_ + i * h_, y0_ + j * h_}, a, b) < clearance)
          free[Index(i, j)] = 0;
      }
    }
  }
  return free;
}

void DistanceField::March(const std::vector<char>& free) {
  d_.assign(free.size(), kNoDistance);
  NodeHeap heap(d_);
  std::vector<int> exit_reached(geometry_.exits.size(), 0);
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const std::size_t n = Index(i, j);
      if (!free[n]) continue;
      const Point2 p{x0_ + i * h_, y0_ + j * h_};
      for (std::size_t k = 0; k < geometry_.exits.size(); ++k) {
        const double dist = DistanceToSegment(p, geometry_.exits[k].a, geometry_.exits[k].b);
        if (dist <= 1.5 * h_ && dist < d_[n]) {
          d_[n] = dist;
          exit_reached[k] = 1;
        }
      }
      if (d_[n] < kNoDistance) heap.Update(static_cast<std::uint32_t>(n));
    }
  }
  for (std::size_t k = 0; k < exit_reached.size(); ++k) {
    if (!exit_reached[k]) {
      throw InputError("clearance",
                       fmt::format("no free grid node within 1.5 spacings of exit {}: the exit is "
                                   "narrower than twice the clearance, or the spacing too coarse",
                                   k));
    }
  }
  const auto value = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return kNoDistance;
    const std::size_t n = Index(i, j);
    return heap.done(n) ? d_[n] : kNoDistance;
  };
  while (!heap.empty()) {
    const std::size_t n = heap.Pop();
    const int i = static_cast<int>(n % static_cast<std::size_t>(nx_));
    const int j = static_cast<int>(n / static_cast<std::size_t>(nx_));
    const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
    for (int q = 0; q < 4; ++q) {
      const int a = i + di[q], b = j + dj[q];
      if (a < 0 || b < 0 || a >= nx_ || b >= ny_) continue;
      const std::size_t m = Index(a, b);
      if (!free[m] || heap.done(m)) continue;
      const double u = EikonalUpdate(std::min(value(a - 1, b), value(a + 1, b)),
                                     std::min(value(a, b - 1), value(a, b + 1)), h_);
      if (u < d_[m]) {
        d_[m] = u;
        heap.Update(static_cast<std::uint32_t>(m));
      }
    }
  }
}

void DistanceField::NodeDirections() {
  const std::size_t nodes = d_.size();
  dir_.assign(2 * nodes, 0.0);
  std::vector<char> has(nodes, 0);
  const auto at = [&](int i, int j) {
    return i < 0 || j < 0 || i >= nx_ || j >= ny_ ? kNoDistance : d_[Index(i, j)];
  };
  // One axis of ∇d at a node of value c from its neighbours' values lo, hi (+∞: none).
  const auto slope = [&](double lo, double c, double hi) {
    if (lo < kNoDistance && hi < kNoDistance) return (hi - lo) / (2.0 * h_);
    if (hi < kNoDistance) return (hi - c) / h_;
    if (lo < kNoDistance) return (c - lo) / h_;
    return 0.0;
  };
  std::vector<std::size_t> layer;
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const std::size_t n = Index(i, j);
      if (!(d_[n] < kNoDistance)) continue;
      const double gx = slope(at(i - 1, j), d_[n], at(i + 1, j));
      const double gy = slope(at(i, j - 1), d_[n], at(i, j + 1));
      const double g = std::hypot(gx, gy);
      if (g > 0.0) {
        dir_[2 * n] = -gx / g;
        dir_[2 * n + 1] = -gy / g;
      }
      has[n] = 1;
    }
  }
  // The rest, layer by layer outward: the normalised mean of the neighbours done before.
  const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
  for (bool more = true; more;) {
    more = false;
    layer.clear();
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        const std::size_t n = Index(i, j);
        if (has[n]) continue;
        double sx = 0.0, sy = 0.0;
        bool any = false;
        for (int q = 0; q < 4; ++q) {
          const int a = i + di[q], b = j + dj[q];
          if (a < 0 || b < 0 || a >= nx_ || b >= ny_ || !has[Index(a, b)]) continue;
          sx += dir_[2 * Index(a, b)];
          sy += dir_[2 * Index(a, b) + 1];
          any = true;
        }
        if (!any) continue;
        const double s = std::hypot(sx, sy);
        dir_[2 * n] = s > 0.0 ? sx / s : 0.0;
        dir_[2 * n + 1] = s > 0.0 ? sy / s : 0.0;
        layer.push_back(n);
      }
    }
    for (const std::size_t n : layer) has[n] = 1;
    more = !layer.empty();
  }
}

double DistanceField::Distance(double x, double y) const {
  const double fx = std::clamp((x - x0_) / h_, 0.0, nx_ - 1.0);
  const double fy = std::clamp((y - y0_) / h_, 0.0, ny_ - 1.0);
  const int i = std::min(static_cast<int>(fx), nx_ - 2);
  const int j = std::min(static_cast<int>(fy), ny_ - 2);
  const double s = fx - i, t = fy - j;
  const double w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
  const double v[4] = {d_[Index(i, j)], d_[Index(i + 1, j)], d_[Index(i, j + 1)],
                       d_[Index(i + 1, j + 1)]};
  double sum = 0.0, weight = 0.0;
  for (int q = 0; q < 4; ++q) {
    if (v[q] < kNoDistance) {
      sum += w[q] * v[q];
      weight += w[q];
    }
  }
  return weight > 0.0 ? sum / weight : kNoDistance;
}

void DistanceField::Direction(const double* x, double* e) const {
  if (!walkable_.Contains(x[0], x[1])) {
    const Point2& n = exit_normal_[geometry_.NearestExit(x[0], x[1])];
    e[0] = n[0];
    e[1] = n[1];
    return;
  }
  const double fx = std::clamp((x[0] - x0_) / h_, 0.0, nx_ - 1.0);
  const double fy = std::clamp((x[1] - y0_) / h_, 0.0, ny_ - 1.0);
  const int i = std::min(static_cast<int>(fx), nx_ - 2);
  const int j = std::min(static_cast<int>(fy), ny_ - 2);
  const double s = fx - i, t = fy - j;
  const std::size_t n[4] = {Index(i, j), Index(i + 1, j), Index(i, j + 1), Index(i + 1, j + 1)};
  const double w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
  double ex = 0.0, ey = 0.0;
  for (int q = 0; q < 4; ++q) {
    ex += w[q] * dir_[2 * n[q]];
    ey += w[q] * dir_[2 * n[q] + 1];
  }
  // ‖(ex, ey)‖ ≤ 1, a weighted mean of unit vectors: the plain root cannot overflow, and it
  // costs a fraction of std::hypot's guarded one (every person at every step of a routed crowd).
  const double norm = std::sqrt(ex * ex + ey * ey);
  e[0] = norm > 0.0 ? ex / norm : 0.0;
  e[1] = norm > 0.0 ? ey / norm : 0.0;
}

}  // namespace moreau::particles
