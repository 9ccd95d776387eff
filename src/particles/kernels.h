// Internal kernels of the particle core (stateless maths): the exact projections onto each set,
// periodic wrapping and images, and the dispatch from run-time dimension to compiled kernels.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
// 2D points, two a vector: [‖xs − a‖², ‖xs − b‖²], each with SquaredNorm<2>'s operations
// (u0² + u1², no fused multiply-add), so the same bits as the scalar pair tests.
inline __m128d SquaredDistances2(__m128d xs, const double* a, const double* b) {
  const __m128d u0 = _mm_sub_pd(xs, _mm_loadu_pd(a));
  const __m128d u1 = _mm_sub_pd(xs, _mm_loadu_pd(b));
  const __m128d q0 = _mm_mul_pd(u0, u0);
  const __m128d q1 = _mm_mul_pd(u1, u1);
  return _mm_add_pd(_mm_unpacklo_pd(q0, q1), _mm_unpackhi_pd(q0, q1));
}

// For each 4-bit mask (bit i: lane i kept): the kept lanes in order, as one vector (the lanes past
// the count are scratch), and their count.
struct CompressTable {
  alignas(16) std::int32_t offset[16][4];
  int count[16];
};
constexpr CompressTable MakeCompressTable() {
  CompressTable t{};
  for (int m = 0; m < 16; ++m) {
    int c = 0;
    for (int b = 0; b < 4; ++b) {
      if ((m >> b) & 1) t.offset[m][c++] = b;
    }
    t.count[m] = c;
  }
  return t;
}
inline constexpr CompressTable kCompress = MakeCompressTable();

// base + i for each set bit i of the 4-bit mask, in order, written at out by one 4-entry store
// (out must have room for 4: the entries past the count are scratch); returns their count.
inline int CompressStore(int mask, int base, int* out) {
  const __m128i offsets = _mm_load_si128(reinterpret_cast<const __m128i*>(kCompress.offset[mask]));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_add_epi32(_mm_set1_epi32(base), offsets));
  return kCompress.count[mask];
}
#endif

// Pair non-overlap ‖X_i − X_j‖ ≥ c for an overlapping pair: u = X_i − X_j (the minimum image on
// periodic axes), r2 = ‖u‖² < c² (the caller's test). Each particle moves by half the overlap along
// u, computed as q · (½ u) with q = (c − r)/r (scaling by ½ is exact away from subnormals, and
// keeps the halving off the dependency chain through the square root and the division).
// Coincident centres separate along axis 0. Returns the distance each particle moved.
template <int K>
inline double ProjectOverlappingPair(double* xi, double* xj, const double* u, double r2, double c) {
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

// The periodic axes of a model: wrapping into [lo, lo + len) and the 27 image shifts
// (code Σ_a (o_a + 1) 3^a for offsets o_a ∈ {−1, 0, 1}; code 13 is no shift).
struct PeriodicBox {
  int k = 2;
  bool any = false;
  bool periodic[3] = {false, false, false};
  double lo[3] = {0.0, 0.0, 0.0};
  double len[3] = {0.0, 0.0, 0.0};
  double shift[27][3] = {};

  static PeriodicBox Of(const ParticleModel& model) {
    PeriodicBox box;
    box.k = model.dimension;
    for (int a = 0; a < box.k; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      box.periodic[a] = model.periodic[ua];
      if (!box.periodic[a]) continue;
      box.any = true;
      box.lo[a] = model.domain_lo[ua];
      box.len[a] = model.domain_hi[ua] - model.domain_lo[ua];
    }
    for (int code = 0; code < 27; ++code) {
      int c = code;
      for (int a = 0; a < 3; ++a) {
        const int o = c % 3 - 1;
        c /= 3;
        box.shift[code][a] = a < box.k ? o * box.len[a] : 0.0;
      }
    }
    return box;
  }

  // x (n points of k coordinates) wrapped into the domain on the periodic axes.
  void WrapAll(double* x, int n) const {
    if (!any) return;
    for (int a = 0; a < k; ++a) {
      if (!periodic[a]) continue;
      for (int s = 0; s < n; ++s) {
        double& v = x[static_cast<std::size_t>(k * s + a)];
        v = Wrap(v, lo[a], len[a]);
      }
    }
  }
};

}  // namespace moreau::particles::internal
