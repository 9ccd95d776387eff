#include "moreau/particles/geometry.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::particles {

namespace {

constexpr std::size_t kMaxVertices = 5000;  // per polygon; edges are checked pairwise
constexpr std::size_t kMaxExits = 1000;
constexpr std::uintmax_t kMaxFileBytes = 16u << 20;

double Cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

double SignedArea(const Polygon2& p) {
  double s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point2& a = p[i];
    const Point2& b = p[(i + 1) % p.size()];
    s += a[0] * b[1] - a[1] * b[0];
  }
  return 0.5 * s;
}

// Whether the closed segments [a, b] and [c, d] share a point (collinear overlaps included).
bool SegmentsMeet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return true;
  }
  const auto on = [](const Point2& p, const Point2& q, const Point2& r, double cr) {
    return cr == 0.0 && std::min(p[0], q[0]) <= r[0] && r[0] <= std::max(p[0], q[0]) &&
           std::min(p[1], q[1]) <= r[1] && r[1] <= std::max(p[1], q[1]);
  };
  return on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4);
}

// Whether edge (a, b) crosses the horizontal line through (x, y) right of x (the even-odd rule's
// count): only an edge with exactly one end above y, i.e. min(a_y, b_y) ≤ y < max(a_y, b_y).
inline bool CrossesRightOf(const Point2& a, const Point2& b, double x, double y) {
  return (a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0];
}

bool InsidePolygon(const Polygon2& p, double x, double y) {
  bool inside = false;
  for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    if (CrossesRightOf(p[i], p[j], x, y)) inside = !inside;
  }
  return inside;
}

// At most this many edge entries in all the strips of a PolygonStrips (fewer strips otherwise).
constexpr std::size_t kMaxStripEntries = std::size_t{1} << 20;

// A polygon's own checks: vertices, area, edges that cross (non-adjacent edges that meet, or
// adjacent ones that fold back onto each other).
void CheckPolygon(const Polygon2& p, const std::string& what) {
  if (p.size() < 3) {
    throw InputError(what, fmt::format("needs at least 3 vertices (got {})", p.size()));
  }
  if (p.size() > kMaxVertices) {
    throw InputError(what, fmt::format("has {} vertices (at most {})", p.size(), kMaxVertices));
  }
  for (const Point2& v : p) {
    if (!std::isfinite(v[0]) || !std::isfinite(v[1])) {
      throw InputError(what, "coordinates must be finite");
    }
  }
  if (!(std::abs(SignedArea(p)) > 0.0)) throw InputError(what, "has zero area");
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    // Adjacent edges (p[i−1], p[i]) and (p[i], p[i+1]) that fold back onto each other.
    const Point2& prev = p[(i + n - 1) % n];
    const Point2& next = p[(i + 1) % n];
    const double back =
        (prev[0] - p[i][0]) * (next[0] - p[i][0]) + (prev[1] - p[i][1]) * (next[1] - p[i][1]);
    if (Cross(prev, p[i], next) == 0.0 && back > 0.0) {
      throw InputError(what, fmt::format("edges {} and {} overlap", (i + n - 1) % n, i));
    }
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent
      if (SegmentsMeet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) {
        throw InputError(what, fmt::format("edges {} and {} cross", i, j));
      }
    }
  }
}

// The index of the walkable polygon's edge that holds exit e, or n when none does.
std::size_t ExitEdge(const Polygon2& w, const CrowdExit& e) {
  for (std::size_t i = 0; i < w.size(); ++i) {
    const Point2& a = w[i];
    const Point2& b = w[(i + 1) % w.size()];
    const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
    const double tol = 1e-9 * std::max(1.0, len);
    if (DistanceToSegment(e.a, a, b) <= tol && DistanceToSegment(e.b, a, b) <= tol) return i;
  }
  return w.size();
}

// Position of p along [a, b] as a fraction of its length.
double Along(const Point2& a, const Point2& b, const Point2& p) {
  const double ab0 = b[0] - a[0], ab1 = b[1] - a[1];
  return ((p[0] - a[0]) * ab0 + (p[1] - a[1]) * ab1) / (ab0 * ab0 + ab1 * ab1);
}

void CheckExits(const CrowdGeometry& g) {
  if (g.exits.empty()) throw InputError("exit", "the geometry needs at least one exit");
  if (g.exits.size() > kMaxExits) {
    throw InputError("exit", fmt::format("{} exits (at most {})", g.exits.size(), kMaxExits));
  }
  std::vector<std::pair<double, double>> spans(g.exits.size());
  std::vector<std::size_t> edges(g.exits.size());
  for (std::size_t k = 0; k < g.exits.size(); ++k) {
    const CrowdExit& e = g.exits[k];
    const std::string what = fmt::format("exit {}", k);
    if (!std::isfinite(e.a[0]) || !std::isfinite(e.a[1]) || !std::isfinite(e.b[0]) ||
        !std::isfinite(e.b[1])) {
      throw InputError(what, "coordinates must be finite");
    }
    if (!(std::hypot(e.b[0] - e.a[0], e.b[1] - e.a[1]) > 0.0)) {
      throw InputError(what, "has zero length");
    }
    edges[k] = ExitEdge(g.walkable, e);
    if (edges[k] == g.walkable.size()) {
      throw InputError(what, "not on an edge of the walkable polygon");
    }
    const Point2& a = g.walkable[edges[k]];
    const Point2& b = g.walkable[(edges[k] + 1) % g.walkable.size()];
    spans[k] = std::minmax(Along(a, b, e.a), Along(a, b, e.b));
    for (std::size_t m = 0; m < k; ++m) {
      if (edges[m] == edges[k] && spans[m].first < spans[k].second &&
          spans[k].first < spans[m].second) {
        throw InputError(what, fmt::format("overlaps exit {}", m));
      }
    }
  }
}

// Every edge of polygon p against every edge of q: whether any two meet.
bool PolygonsMeet(const Polygon2& p, const Polygon2& q) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = 0; j < q.size(); ++j) {
      if (SegmentsMeet(p[i], p[(i + 1) % p.size()], q[j], q[(j + 1) % q.size()])) return true;
    }
  }
  return false;
}

}  // namespace

double DistanceToSegment(const Point2& p, const Point2& a, const Point2& b) {
  const double ab0 = b[0] - a[0], ab1 = b[1] - a[1];
  const double l2 = ab0 * ab0 + ab1 * ab1;
  const double t =
      l2 > 0.0 ? std::clamp(((p[0] - a[0]) * ab0 + (p[1] - a[1]) * ab1) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(p[0] - (a[0] + t * ab0), p[1] - (a[1] + t * ab1));
}

void CrowdGeometry::Validate() const {
  CheckPolygon(walkable, "walkable");
  std::size_t vertices = walkable.size();
  for (const Polygon2& p : obstacles) vertices += p.size();
  if (vertices > 4 * kMaxVertices) {
    throw InputError("obstacle",
                     fmt::format("{} vertices in all (at most {})", vertices, 4 * kMaxVertices));
  }
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    const std::string what = fmt::format("obstacle {}", k);
    CheckPolygon(obstacles[k], what);
    if (PolygonsMeet(obstacles[k], walkable) ||
        !InsidePolygon(walkable, obstacles[k][0][0], obstacles[k][0][1])) {
      throw InputError(what, "not inside the walkable polygon (apart from its edges)");
    }
    for (std::size_t m = 0; m < k; ++m) {
      if (PolygonsMeet(obstacles[k], obstacles[m]) ||
          InsidePolygon(obstacles[m], obstacles[k][0][0], obstacles[k][0][1]) ||
          InsidePolygon(obstacles[k], obstacles[m][0][0], obstacles[m][0][1])) {
        throw InputError(what, fmt::format("overlaps obstacle {}", m));
      }
    }
  }
  CheckExits(*this);
}

PolygonStrips::PolygonStrips(const Polygon2& polygon) {
  if (polygon.empty()) return;
  y0_ = y1_ = polygon[0][1];
  for (const Point2& v : polygon) {
    y0_ = std::min(y0_, v[1]);
    y1_ = std::max(y1_, v[1]);
  }
  // The edges in InsidePolygon's order and orientation; a level edge never crosses a line.
  std::vector<Edge> edges;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    if (polygon[i][1] != polygon[j][1]) edges.push_back({polygon[i], polygon[j]});
  }
  const auto entries = [&] {
    std::size_t n = 0;
    for (const Edge& e : edges) {
      n += static_cast<std::size_t>(Strip(std::max(e.a[1], e.b[1])) -
                                    Strip(std::min(e.a[1], e.b[1])) + 1);
    }
    return n;
  };
  strips_ = static_cast<int>(std::clamp<std::size_t>(edges.size(), 1, 4096));
  for (;; strips_ /= 2) {
    height_ = y1_ > y0_ ? (y1_ - y0_) / strips_ : 1.0;
    if (strips_ == 1 || entries() <= kMaxStripEntries) break;
  }
  // Strip(v) is non-decreasing in v, so an edge with lo ≤ y ≤ hi is listed in y's strip.
  std::vector<std::vector<Edge>> bins(static_cast<std::size_t>(strips_));
  for (const Edge& e : edges) {
    for (int k = Strip(std::min(e.a[1], e.b[1])); k <= Strip(std::max(e.a[1], e.b[1])); ++k) {
      bins[static_cast<std::size_t>(k)].push_back(e);
    }
  }
  begin_.assign(1, 0);
  for (const std::vector<Edge>& bin : bins) {
    edges_.insert(edges_.end(), bin.begin(), bin.end());
    begin_.push_back(static_cast<int>(edges_.size()));
  }
}

int PolygonStrips::Strip(double y) const {
  return std::clamp(static_cast<int>((y - y0_) / height_), 0, strips_ - 1);
}

bool PolygonStrips::Contains(double x, double y) const {
  // Outside [y0, y1] (or NaN) every edge has both ends on one side of the line: no crossing.
  if (strips_ == 0 || !(y >= y0_ && y <= y1_)) return false;
  const int k = Strip(y);
  bool inside = false;
  const auto strip = static_cast<std::size_t>(k);
  const Edge* const end = edges_.data() + begin_[strip + 1];
  for (const Edge* e = edges_.data() + begin_[strip]; e != end; ++e) {
    if (CrossesRightOf(e->a, e->b, x, y)) inside = !inside;
  }
  return inside;
}

std::vector<SegmentObstacle> CrowdGeometry::Walls() const {
  std::vector<SegmentObstacle> walls;
  const std::size_t n = walkable.size();
  std::vector<std::size_t> exit_edge(exits.size());
  for (std::size_t k = 0; k < exits.size(); ++k) exit_edge[k] = ExitEdge(walkable, exits[k]);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& a = walkable[i];
    const Point2& b = walkable[(i + 1) % n];
    std::vector<std::pair<double, double>> cuts;  // the exits on this edge, as fractions
    for (std::size_t k = 0; k < exits.size(); ++k) {
      if (exit_edge[k] == i)
        cuts.push_back(std::minmax(Along(a, b, exits[k].a), Along(a, b, exits[k].b)));
    }
    std::sort(cuts.begin(), cuts.end());
    double from = 0.0;
    const auto add = [&](double t0, double t1) {
      if (!(t1 - t0 > 1e-12)) return;
      walls.push_back({{a[0] + t0 * (b[0] - a[0]), a[1] + t0 * (b[1] - a[1])},
                       {a[0] + t1 * (b[0] - a[0]), a[1] + t1 * (b[1] - a[1])}});
    };
    for (const auto& [t0, t1] : cuts) {
      add(from, t0);
      from = std::max(from, t1);
    }
    add(from, 1.0);
  }
  for (const Polygon2& p : obstacles) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Point2& a = p[i];
      const Point2& b = p[(i + 1) % p.size()];
      walls.push_back({a, b});
    }
  }
  return walls;
}

bool CrowdGeometry::InsideWalkablePolygon(double x, double y) const {
  return InsidePolygon(walkable, x, y);
}

bool CrowdGeometry::Walkable(double x, double y) const {
  if (!InsidePolygon(walkable, x, y)) return false;
  for (const Polygon2& p : obstacles) {
    if (InsidePolygon(p, x, y)) return false;
  }
  return true;
}

Point2 CrowdGeometry::ExitNormal(std::size_t k) const {
  const CrowdExit& e = exits[k];
  const double t0 = e.b[0] - e.a[0], t1 = e.b[1] - e.a[1];
  const double len = std::hypot(t0, t1);
  Point2 n{t1 / len, -t0 / len};
  // Outward: a point just beyond the exit's midpoint along n is outside the polygon.
  const double step = 1e-6 * std::max(1.0, len);
  const double mx = 0.5 * (e.a[0] + e.b[0]), my = 0.5 * (e.a[1] + e.b[1]);
  if (InsidePolygon(walkable, mx + step * n[0], my + step * n[1])) n = {-n[0], -n[1]};
  return n;
}

std::size_t CrowdGeometry::NearestExit(double x, double y) const {
  std::size_t best = 0;
  double best_d = DistanceToSegment({x, y}, exits[0].a, exits[0].b);
  for (std::size_t k = 1; k < exits.size(); ++k) {
    const double d = DistanceToSegment({x, y}, exits[k].a, exits[k].b);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return best;
}

bool CrowdGeometry::BoxWalkable(const Point2& lo, const Point2& hi) const {
  const Point2 corners[4] = {lo, {hi[0], lo[1]}, hi, {lo[0], hi[1]}};
  for (const Point2& c : corners) {
    if (!Walkable(c[0], c[1])) return false;
  }
  for (const SegmentObstacle& w : Walls()) {
    if (w.a[0] >= lo[0] && w.a[0] <= hi[0] && w.a[1] >= lo[1] && w.a[1] <= hi[1]) return false;
    for (int i = 0; i < 4; ++i) {
      if (SegmentsMeet({w.a[0], w.a[1]}, {w.b[0], w.b[1]}, corners[i], corners[(i + 1) % 4])) {
        return false;
      }
    }
  }
  return true;
}

namespace {

// The numbers of one line after its keyword: InputError(reason) for a word that is not a finite
// number.
std::vector<double> ParseNumbers(std::istringstream& words) {
  std::vector<double> v;
  std::string w;
  while (words >> w) {
    double x = 0.0;
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), x);
    if (ec != std::errc() || end != w.data() + w.size() || !std::isfinite(x)) {
      throw InputError(fmt::format("{} is not a finite number", w));
    }
    v.push_back(x);
  }
  return v;
}

Polygon2 ToPolygon(const std::vector<double>& v) {
  if (v.size() % 2 != 0) throw InputError("expected an even number of coordinates (x y pairs)");
  Polygon2 p(v.size() / 2);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = {v[2 * i], v[2 * i + 1]};
  return p;
}

}  // namespace

CrowdGeometry ParseCrowdGeometry(std::string_view text, std::string_view name) {
  CrowdGeometry g;
  std::map<std::string, int> line_of;  // "walkable", "obstacle K", "exit K" → line
  std::istringstream lines{std::string(text)};
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    try {
      const Polygon2 p = ToPolygon(ParseNumbers(words));
      if (keyword == "walkable") {
        if (!g.walkable.empty()) throw InputError("a second walkable polygon (give one)");
        if (p.empty()) throw InputError("walkable: needs at least 3 vertices (got 0)");
        g.walkable = p;
        line_of["walkable"] = number;
      } else if (keyword == "obstacle") {
        line_of[fmt::format("obstacle {}", g.obstacles.size())] = number;
        g.obstacles.push_back(p);
      } else if (keyword == "exit") {
        if (p.size() != 2) {
          throw InputError(fmt::format("an exit is a segment: 4 numbers (got {})", 2 * p.size()));
        }
        line_of[fmt::format("exit {}", g.exits.size())] = number;
        g.exits.push_back({p[0], p[1]});
      } else {
        throw InputError(fmt::format("unknown keyword '{}' (walkable, obstacle or exit)", keyword));
      }
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}:{}: {}", name, number, e.what()));
    }
  }
  if (g.walkable.empty()) throw InputError(fmt::format("{}: no walkable polygon", name));
  try {
    g.Validate();
  } catch (const InputError& e) {
    const auto at = line_of.find(e.key());
    if (at == line_of.end()) throw InputError(fmt::format("{}: {}", name, e.what()));
    throw InputError(fmt::format("{}:{}: {}", name, at->second, e.what()));
  }
  return g;
}

CrowdGeometry ReadCrowdGeometry(const std::string& path, std::string_view name) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
    throw InputError(fmt::format("{}: not a regular file", name));
  }
  if (const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
      !ec && bytes > kMaxFileBytes) {
    throw InputError(fmt::format("{}: {} bytes (at most {})", name, bytes, kMaxFileBytes));
  }
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot be read", name));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseCrowdGeometry(text.str(), name);
}

}  // namespace moreau::particles
