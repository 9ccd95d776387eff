#include "particles/sweep.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "particles/kernels.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

namespace {
constexpr int kAhead = 64;  // slots ahead to prefetch in the sweep

#if defined(__SSE2__)
// Equal radii in 2D: a row of `count` ≤ 4 pairs from slot p (nearly all rows) tested whole, with
// no branch per pair: the pair test's ‖u‖² (SquaredDistances2, two pairs a vector) for 4 entries
// from p on (those past the row are other rows' partners, valid slots, and masked out). True when
// no pair overlaps (r² ≥ c², which also fails for NaN): the row projects nothing, and only the
// near-contact test is left (R: s appended to *near when a pair lies closer than near2).
template <bool R>
[[gnu::always_inline]] inline bool UniformRowClear2(__m128d xv, const double* x, const int* nb,
                                                    std::int64_t p, int count, double c2,
                                                    double near2, int s, std::vector<int>* near) {
  auto r2_of = [&](std::int64_t q) {  // the pairs q and q + 1
    return SquaredDistances2(xv, x + 2 * static_cast<std::ptrdiff_t>(nb[q]),
                             x + 2 * static_cast<std::ptrdiff_t>(nb[q + 1]));
  };
  const __m128d lo = r2_of(p), hi = r2_of(p + 2);
  const int valid = (1 << count) - 1;
  const __m128d c2v = _mm_set1_pd(c2);
  const int over_lo = _mm_movemask_pd(_mm_cmpnge_pd(lo, c2v));
  const int over_hi = _mm_movemask_pd(_mm_cmpnge_pd(hi, c2v));
  if (((over_lo | (over_hi << 2)) & valid) != 0) return false;
  if constexpr (R) {
    const __m128d near2v = _mm_set1_pd(near2);
    const int near_lo = _mm_movemask_pd(_mm_cmplt_pd(lo, near2v));
    const int near_hi = _mm_movemask_pd(_mm_cmplt_pd(hi, near2v));
    if ((near_lo | (near_hi << 2)) & valid) near->push_back(s);
  }
  return true;
}
#endif
}  // namespace

ProjectionSweep::ProjectionSweep(const ParticleModel& model, bool uniform_radius)
    : k_(model.dimension), n_(model.count()), uniform_radius_(uniform_radius) {
  for (const UnitWall& w : UnitWalls(model)) {
    for (int a = 0; a < k_; ++a) wall_n_.push_back(w.n[a]);
    wall_b_.push_back(w.b);
  }
  for (const SphereObstacle& o : model.spheres) {
    for (int a = 0; a < k_; ++a) sphere_c_.push_back(o.center[static_cast<std::size_t>(a)]);
    sphere_r_.push_back(o.radius);
  }
  for (const SegmentObstacle& g : model.segments) {
    seg_a_.insert(seg_a_.end(), {g.a[0], g.a[1]});
    seg_b_.insert(seg_b_.end(), {g.b[0], g.b[1]});
  }
  fixed_sets_ = static_cast<int>(model.walls.size() + model.spheres.size() + model.segments.size());
  seg_reach_ = model.count() > 0 ? model.max_radius() : 0.0;
  if (model.segments.size() > 4 && seg_reach_ > 0.0) {
    seg_grid_ = SegmentGrid(seg_a_, seg_b_, 2.0 * seg_reach_, 256);
  }
  path_.assign(static_cast<std::size_t>(n_), 0.0);
  start_.assign(static_cast<std::size_t>(k_) * static_cast<std::size_t>(n_), 0.0);
  stamp_.assign(static_cast<std::size_t>(n_), 0);
}

// The pairs of rows [begin, end). X_s stays in registers over its row (the pairs (s, ·) are
// consecutive and no other pair touches X_s in between) and is written back only if it moved.
// R: rows with a pair closer than c + margin are appended to *near.
template <int K, bool P, bool U, bool R>
void ProjectionSweep::SweepRows(int begin, int end, double* x, const double* radius,
                                const NeighbourList& list, double* max_path, std::int64_t* proj,
                                double margin, std::vector<int>* near) {
  const int* rs = list.row_start();
  [[maybe_unused]] const std::int64_t pairs = list.pairs();
  const int* nb = list.neighbours();
  const std::uint8_t* image = list.images();
  const double(*shift)[3] = list.box().shift;
  const double uniform_c = 2.0 * radius[0];  // r_i + r_j when all radii are equal (exact)
  const double uniform_c2 = uniform_c * uniform_c;
  const double uniform_near2 = (uniform_c + margin) * (uniform_c + margin);
  double local_max = *max_path;
  std::int64_t moved = 0;
  // The non-empty rows of [begin, end) only (an empty row does nothing).
  const int* first = std::lower_bound(list.active_rows(), list.active_rows_end(), begin);
  const int* last = std::lower_bound(first, list.active_rows_end(), end);
  for (const int* row = first; row != last; ++row) {
    const int s = *row;
    // Partners lie mostly within a few dozen slots ahead (the half list over cell order): the
    // positions and path marks a little ahead are fetched early.
    const int ahead = std::min(s + kAhead, n_ - 1);  // stays inside the arrays
    __builtin_prefetch(x + K * ahead);
    std::int64_t p = rs[s];
    const std::int64_t e = rs[s + 1];
    double* xs_mem = x + K * s;
    double xs[K];
    for (int a = 0; a < K; ++a) xs[a] = xs_mem[a];
#if defined(__SSE2__)
    if constexpr (K == 2 && !P && U) {
      if (e - p <= 4 && p + 4 <= pairs &&
          UniformRowClear2<R>(_mm_loadu_pd(xs), x, nb, p, static_cast<int>(e - p), uniform_c2,
                              uniform_near2, s, near)) {
        continue;
      }
    }
#endif
    const double ri = U ? 0.0 : radius[s];
    double add = 0.0;
    bool near_row = false;
    for (; p < e; ++p) {
      const int t = nb[p];
      double* xt = x + K * t;
      double u[K];
      for (int a = 0; a < K; ++a) u[a] = xs[a] - xt[a];
      if constexpr (P) {
        const int code = image[p];
        if (code != 13) {
          for (int a = 0; a < K; ++a) u[a] -= shift[code][a];
        }
      }
      const double c = U ? uniform_c : ri + radius[t];
      const double r2 = SquaredNorm<K>(u);
      if constexpr (R) near_row |= r2 < (U ? uniform_near2 : (c + margin) * (c + margin));
      if (r2 >= (U ? uniform_c2 : c * c)) continue;
      KeepStart<K>(t, xt);
      const double d = ProjectOverlappingPair<K>(xs, xt, u, r2, c);
      add += d;
      local_max = std::max(local_max, AddPath(t, d));
      ++moved;
    }
    if (add > 0.0) {
      KeepStart<K>(s, xs_mem);
      for (int a = 0; a < K; ++a) xs_mem[a] = xs[a];
      local_max = std::max(local_max, AddPath(s, add));
    }
    if constexpr (R) {
      if (near_row) near->push_back(s);
    }
  }
  *max_path = local_max;
  *proj += moved;
}

template <int K>
void ProjectionSweep::SweepFixed(int begin, int end, double* x, const double* radius,
                                 double* max_path, std::int64_t* proj) {
  const int walls = static_cast<int>(wall_b_.size());
  const int spheres = static_cast<int>(sphere_r_.size());
  const int segments = static_cast<int>(seg_a_.size() / 2);
  double local_max = *max_path;
  std::int64_t moved = 0;
  for (int s = begin; s < end; ++s) {
    double* xs = x + K * s;
    const double r = radius[s];
    double before[K];
    for (int a = 0; a < K; ++a) before[a] = xs[a];
    double add = 0.0;
    auto count = [&](double d) {
      if (d > 0.0) {
        add += d;
        ++moved;
      }
    };
    for (int w = 0; w < walls; ++w) {
      count(ProjectWall<K>(xs, &wall_n_[static_cast<std::size_t>(K * w)],
                           wall_b_[static_cast<std::size_t>(w)] + r));
    }
    for (int o = 0; o < spheres; ++o) {
      count(ProjectSphereExterior<K>(xs, &sphere_c_[static_cast<std::size_t>(K * o)],
                                     sphere_r_[static_cast<std::size_t>(o)] + r));
    }
    if constexpr (K == 2) {
      int g = 0;  // the segments before g are done
      if (seg_grid_.active() && r <= seg_reach_ && std::isfinite(xs[0]) && std::isfinite(xs[1])) {
        // The start cell's segments; the others are farther than 2 max r from xs0, so no-ops
        // while xs stays within max r of xs0; past that, every segment after the last one done.
        const double xs0[2] = {xs[0], xs[1]};
        const int* first = nullptr;
        const int* last = nullptr;
        seg_grid_.Near(xs0, &first, &last);
        g = segments;
        for (; first != last; ++first) {
          const int q = *first;
          const double d = ProjectSegmentExterior(xs, &seg_a_[static_cast<std::size_t>(2 * q)],
                                                  &seg_b_[static_cast<std::size_t>(2 * q)], r);
          count(d);
          const double m0 = xs[0] - xs0[0], m1 = xs[1] - xs0[1];
          if (d > 0.0 && !(m0 * m0 + m1 * m1 < 0.25 * seg_reach_ * seg_reach_)) {
            g = q + 1;
            break;
          }
        }
      }
      for (; g < segments; ++g) {
        count(ProjectSegmentExterior(xs, &seg_a_[static_cast<std::size_t>(2 * g)],
                                     &seg_b_[static_cast<std::size_t>(2 * g)], r));
      }
    }
    if (add > 0.0) {
      KeepStart<K>(s, before);
      local_max = std::max(local_max, AddPath(s, add));
    }
  }
  *max_path = local_max;
  *proj += moved;
}

template <int K, bool P>
double ProjectionSweep::SweepImpl(double* x, const double* radius, const NeighbourList& list,
                                  const Colouring& colouring, const CellList& cells,
                                  bool lexicographic, int threads, std::int64_t* projections,
                                  NearContactRows* near) {
  const int n = n_;
  const double margin = near != nullptr ? near->margin : 0.0;
  auto rows = [&](int begin, int end, double* max_path, std::int64_t* proj) {
    std::vector<int>* mine =
        near != nullptr ? &near->rows[static_cast<std::size_t>(omp_get_thread_num())] : nullptr;
    if (uniform_radius_) {
      if (mine != nullptr) {
        SweepRows<K, P, true, true>(begin, end, x, radius, list, max_path, proj, margin, mine);
      } else {
        SweepRows<K, P, true, false>(begin, end, x, radius, list, max_path, proj, 0.0, nullptr);
      }
    } else if (mine != nullptr) {
      SweepRows<K, P, false, true>(begin, end, x, radius, list, max_path, proj, margin, mine);
    } else {
      SweepRows<K, P, false, false>(begin, end, x, radius, list, max_path, proj, 0.0, nullptr);
    }
  };
  double max_path = 0.0;
  std::int64_t proj = 0;
  if (lexicographic) {
    rows(0, n, &max_path, &proj);
    if (fixed_sets_ > 0) SweepFixed<K>(0, n, x, radius, &max_path, &proj);
    *projections += proj;
    if (near != nullptr) near->max_path = max_path;
    return max_path;
  }
  progress_.Start(colouring.blocks());
#pragma omp parallel num_threads(threads) reduction(max : max_path) reduction(+ : proj)
  {
    ForEachBlockInDependencyOrder(colouring, cells, progress_,
                                  [&](int begin, int end) { rows(begin, end, &max_path, &proj); });
    if (fixed_sets_ > 0) {
#pragma omp barrier
#pragma omp for schedule(static)
      for (int chunk = 0; chunk < (n + 1023) / 1024; ++chunk) {
        SweepFixed<K>(chunk * 1024, std::min(n, chunk * 1024 + 1024), x, radius, &max_path, &proj);
      }
    }
  }
  *projections += proj;
  if (near != nullptr) near->max_path = max_path;
  return max_path;
}

double ProjectionSweep::Sweep(StepContext& context, std::int64_t* projections,
                              NearContactRows* near) {
  ++sweep_id_;
  if (sweep_id_ == 0) {  // wrapped around: clear the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0);
    sweep_id_ = 1;
  }
  double* x = context.store->predicted.data();
  const double* radius = context.store->radius.data();
  return DispatchDimensionPeriodic(k_, context.list.box().any, [&](auto kk, auto p) {
    return SweepImpl<kk, p>(x, radius, context.list, context.colouring, context.cells,
                            context.lexicographic, context.threads, projections, near);
  });
}

void ProjectionSweep::StartPositions(const double* x, std::vector<double>* start) const {
  const int k = k_;
  start->resize(static_cast<std::size_t>(k) * static_cast<std::size_t>(n_));
  double* out = start->data();
  for (int s = 0; s < n_; ++s) {
    const bool moved = stamp_[static_cast<std::size_t>(s)] == sweep_id_;
    const double* from = moved ? start_.data() + static_cast<std::ptrdiff_t>(k) * s : x + k * s;
    for (int a = 0; a < k; ++a) out[k * s + a] = from[a];
  }
}

double ProjectionSweep::MaxFixedViolation(const double* x, const double* radius) const {
  const int k = k_;
  double worst = 0.0;
  for (int s = 0; s < n_; ++s) {
    const double* xs = x + k * s;
    const double r = radius[s];
    for (std::size_t w = 0; w < wall_b_.size(); ++w) {
      double g = -(wall_b_[w] + r);
      for (int a = 0; a < k; ++a)
        g += wall_n_[static_cast<std::size_t>(k) * w + static_cast<std::size_t>(a)] * xs[a];
      worst = std::max(worst, -g);
    }
    for (std::size_t o = 0; o < sphere_r_.size(); ++o) {
      double r2 = 0.0;
      for (int a = 0; a < k; ++a) {
        const double d =
            xs[a] - sphere_c_[static_cast<std::size_t>(k) * o + static_cast<std::size_t>(a)];
        r2 += d * d;
      }
      worst = std::max(worst, sphere_r_[o] + r - std::sqrt(r2));
    }
    for (std::size_t g = 0; g < seg_a_.size() / 2; ++g) {
      worst = std::max(worst, -SegmentGap(xs, &seg_a_[2 * g], &seg_b_[2 * g], r));
    }
  }
  return worst;
}

}  // namespace moreau::particles::internal
