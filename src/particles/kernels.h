// Internal kernels of the particle engine: the exact projections onto each set, periodic
// wrapping, and a small linked-cell grid for the O(N) checks outside the hot loop.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "moreau/particles/model.h"

namespace moreau::particles::internal {

// The one dispatch from run-time (dimension, periodicity) to compile-time kernels:
// DispatchDimension(k, f) calls f(std::integral_constant<int, k>{}) for k ∈ {1, 2, 3};
// DispatchDimensionPeriodic(k, periodic, f) calls f(integral_constant<int, k>, bool_constant<p>)
// for k ∈ {2, 3} (the engine's dimensions). Returns what f returns.
template <typename F>
inline decltype(auto) DispatchDimension(int k, F&& f) {
  if (k == 1) return f(std::integral_constant<int, 1>{});
  if (k == 2) return f(std::integral_constant<int, 2>{});
  return f(std::integral_constant<int, 3>{});
}

template <typename F>
inline decltype(auto) DispatchDimensionPeriodic(int k, bool periodic, F&& f) {
  if (k == 2) {
    if (periodic) return f(std::integral_constant<int, 2>{}, std::true_type{});
    return f(std::integral_constant<int, 2>{}, std::false_type{});
  }
  if (periodic) return f(std::integral_constant<int, 3>{}, std::true_type{});
  return f(std::integral_constant<int, 3>{}, std::false_type{});
}

template <int K>
inline double SquaredNorm(const double* u) {
  double r2 = u[0] * u[0];
  for (int c = 1; c < K; ++c) r2 += u[c] * u[c];
  return r2;
}

// Pair non-overlap ‖X_i − X_j‖ ≥ c for an overlapping pair: u = X_i − X_j (the minimum image on
// periodic axes), r2 = ‖u‖² < c² (the caller's test). Each particle moves by half the overlap along
// u, computed as q · (½ u) with q = (c − r)/r (scaling by ½ is exact away from subnormals, and
// keeps the halving off the dependency chain through the square root and the division).
// Coincident centres separate along axis 0. Returns the distance each particle moved.
template <int K>
inline double ProjectOverlappingPair(double* xi, double* xj, const double* u, double r2,
                                     double c) {
  const double r = std::sqrt(r2);
  if (r > 0.0) {
    const double q = (c - r) / r;
    for (int a = 0; a < K; ++a) {
      const double step = q * (0.5 * u[a]);
      xi[a] += step;
      xj[a] -= step;
    }
    return 0.5 * (c - r);
  }
  xi[0] += 0.5 * c;
  xj[0] -= 0.5 * c;
  return 0.5 * c;
}

// The pair projection with its test: the identity when ‖u‖ ≥ c. Returns the distance each
// particle moved (0 if none).
template <int K>
inline double ProjectPair(double* xi, double* xj, const double* u, double c) {
  const double r2 = SquaredNorm<K>(u);
  if (r2 >= c * c) return 0.0;
  return ProjectOverlappingPair<K>(xi, xj, u, r2, c);
}

// A wall with a unit normal: ⟨n, X⟩ ≥ b + r_i, from a model Wall (n = normal/‖normal‖,
// b = offset/‖normal‖ with ‖normal‖ summed over the first k components). Axes ≥ k are 0.
struct UnitWall {
  double n[3] = {0.0, 0.0, 0.0};
  double b = 0.0;
};

inline UnitWall Normalize(const Wall& wall, int k) {
  double n2 = 0.0;
  for (int a = 0; a < k; ++a) {
    n2 += wall.normal[static_cast<std::size_t>(a)] * wall.normal[static_cast<std::size_t>(a)];
  }
  const double len = std::sqrt(n2);
  UnitWall u;
  for (int a = 0; a < k; ++a) u.n[a] = wall.normal[static_cast<std::size_t>(a)] / len;
  u.b = wall.offset / len;
  return u;
}

inline std::vector<UnitWall> UnitWalls(const ParticleModel& model) {
  std::vector<UnitWall> out;
  out.reserve(model.walls.size());
  for (const Wall& w : model.walls) out.push_back(Normalize(w, model.dimension));
  return out;
}

// The gap ⟨n, X⟩ − b − r of particle X (radius r) to a unit wall, the dot product summed in
// component order (negative inside the wall).
inline double WallGap(const UnitWall& w, const double* x, int k, double r) {
  double dot = w.n[0] * x[0];
  for (int a = 1; a < k; ++a) dot += w.n[a] * x[a];
  return dot - w.b - r;
}

// Half-space ⟨n, X⟩ ≥ b, n unit: X ← X − min(0, ⟨n, X⟩ − b) n (the foundation's arithmetic:
// g = −b + Σ n_a X_a). Returns the distance moved.
template <int K>
inline double ProjectWall(double* x, const double* n, double b) {
  double g = -b;
  for (int a = 0; a < K; ++a) g += n[a] * x[a];
  if (g >= 0.0) return 0.0;
  for (int a = 0; a < K; ++a) x[a] -= g * n[a];
  return -g;
}

// Exterior of the ball ‖X − c‖ ≥ R: radial push to the sphere; the centre itself goes along +e_0.
template <int K>
inline double ProjectSphereExterior(double* x, const double* center, double R) {
  double d[K];
  for (int a = 0; a < K; ++a) d[a] = x[a] - center[a];
  const double r2 = SquaredNorm<K>(d);
  if (r2 >= R * R) return 0.0;
  const double r = std::sqrt(r2);
  if (r > 0.0) {
    const double q = (R - r) / r;
    for (int a = 0; a < K; ++a) x[a] += q * d[a];
    return R - r;
  }
  x[0] += R;
  return R;
}

// dist(X, [a, b]) ≥ R in 2D (the exterior of a capsule, whose projection is the radial push from
// the nearest point q of the segment); a point on the segment goes along the left normal of b − a.
inline double ProjectSegmentExterior(double* x, const double* a, const double* b, double R) {
  const double e0 = b[0] - a[0];
  const double e1 = b[1] - a[1];
  const double len2 = e0 * e0 + e1 * e1;
  double t = ((x[0] - a[0]) * e0 + (x[1] - a[1]) * e1) / len2;
  t = std::clamp(t, 0.0, 1.0);
  const double q0 = a[0] + t * e0;
  const double q1 = a[1] + t * e1;
  const double d0 = x[0] - q0;
  const double d1 = x[1] - q1;
  const double r2 = d0 * d0 + d1 * d1;
  if (r2 >= R * R) return 0.0;
  const double r = std::sqrt(r2);
  if (r > 0.0) {
    const double q = (R - r) / r;
    x[0] += q * d0;
    x[1] += q * d1;
    return R - r;
  }
  const double len = std::sqrt(len2);
  x[0] = q0 - R * e1 / len;
  x[1] = q1 + R * e0 / len;
  return R;
}

// Signed gap dist(X, [a, b]) − R (2D).
inline double SegmentGap(const double* x, const double* a, const double* b, double R) {
  const double e0 = b[0] - a[0];
  const double e1 = b[1] - a[1];
  const double len2 = e0 * e0 + e1 * e1;
  const double t = std::clamp(((x[0] - a[0]) * e0 + (x[1] - a[1]) * e1) / len2, 0.0, 1.0);
  const double d0 = x[0] - (a[0] + t * e0);
  const double d1 = x[1] - (a[1] + t * e1);
  return std::sqrt(d0 * d0 + d1 * d1) - R;
}

// v wrapped into [lo, lo + L).
inline double Wrap(double v, double lo, double L) {
  double t = v - lo;
  if (t >= 0.0 && t < L) return v;
  t -= L * std::floor(t / L);
  if (t >= L || t < 0.0) t = 0.0;
  return lo + t;
}

// The minimum-image component of a displacement d on an axis of length L (|d| < L assumed after
// wrapping both ends; larger |d| are reduced with rounding).
inline double MinimumImage(double d, double L) {
  if (d > 0.5 * L) return d - L * std::round(d / L);
  if (d < -0.5 * L) return d - L * std::round(d / L);
  return d;
}

// A linked-cell grid over wrapped positions for validation and initial states (not the engine's
// hot path): cells of edge ≥ `edge` over [lo, hi] (periodic axes: the domain), particles linked
// per cell. Cell coordinates are clamped, which keeps pairs within `edge` in adjacent cells.
class LinkedCells {
 public:
  LinkedCells(int k, const Vec3& lo, const Vec3& hi, const std::array<bool, 3>& periodic,
              double edge, std::int64_t max_cells);
  void Insert(int particle, const double* x);
  // Calls f(j) for every inserted particle j in the cells around x (each once).
  template <typename F>
  void ForEachNear(const double* x, F&& f) const {
    int c[3] = {0, 0, 0};
    for (int a = 0; a < k_; ++a) c[a] = Coord(a, x[a]);
    int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int a = 0; a < k_; ++a) {
      if (periodic_[static_cast<std::size_t>(a)] && n_[a] >= 3) {
        lo[a] = c[a] - 1;
        hi[a] = c[a] + 1;
      } else if (periodic_[static_cast<std::size_t>(a)]) {
        lo[a] = 0;
        hi[a] = n_[a] - 1;
      } else {
        lo[a] = std::max(0, c[a] - 1);
        hi[a] = std::min(n_[a] - 1, c[a] + 1);
      }
    }
    for (int z = lo[2]; z <= hi[2]; ++z) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int xx = lo[0]; xx <= hi[0]; ++xx) {
          const std::int64_t cell = Index(Norm(0, xx), Norm(1, y), Norm(2, z));
          for (int j = head_[static_cast<std::size_t>(cell)]; j >= 0;
               j = next_[static_cast<std::size_t>(j)]) {
            f(j);
          }
        }
      }
    }
  }

 private:
  int Coord(int a, double v) const;
  int Norm(int a, int c) const { return c < 0 ? c + n_[a] : (c >= n_[a] ? c - n_[a] : c); }
  std::int64_t Index(int x, int y, int z) const {
    return (static_cast<std::int64_t>(z) * n_[1] + y) * n_[0] + x;
  }
  int k_;
  int n_[3] = {1, 1, 1};
  double lo_[3] = {0, 0, 0};
  double inv_[3] = {0, 0, 0};
  std::array<bool, 3> periodic_;
  std::vector<int> head_;
  std::vector<int> next_;
};

}  // namespace moreau::particles::internal
