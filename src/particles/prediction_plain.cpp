// The prediction's loop for a drift of at most the trap and active velocities (Prediction::Plain):
// no branches, the general loop's arithmetic (prediction.cpp), tested bit for bit against it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "particles/noise.h"
#include "particles/prediction.h"

namespace moreau::particles::internal {

namespace {

// A batch with a row that is not finite: its worst move and extent over the finite rows only (as
// PredictImpl), and the smallest id of a row that is not.
template <int K>
std::int64_t RescanFinite(const double* x, const double* y, const int* id, int begin, int end,
                          double* worst, double* extent) {
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();
  *worst = *extent = 0.0;
  for (int s = begin; s < end; ++s) {
    double d2 = 0.0, far = 0.0;
    bool row_finite = true;
    for (int a = 0; a < K; ++a) {
      const double ya = y[K * s + a], dd = ya - x[K * s + a];
      row_finite = row_finite && std::isfinite(ya);
      d2 += dd * dd;
      far = std::max(far, std::abs(ya));
    }
    if (!row_finite) {
      bad = std::min<std::int64_t>(bad, id[s]);
    } else {
      *worst = std::max(*worst, d2);
      *extent = std::max(*extent, far);
    }
  }
  return bad;
}

#if defined(__SSE2__)
// The constants of the plain prediction: F = −γ (x − c), y = x + h (F + a) (+ σ ξ), a the active
// velocity; reach² of the bound.
struct PlainConstants {
  double g, h, sigma, reach2;
  double c[2];
};

// The 2D vector path's running maxima, lane by lane: ‖Y − X‖², |Y| and ‖Y − R‖².
struct Maxima2 {
  __m128d worst = _mm_setzero_pd(), extent = _mm_setzero_pd(), worst2 = _mm_setzero_pd();
  // Folded into the scalar maxima.
  void Fold(double* w, double* e, double* w2) const {
    double lanes[2];
    _mm_storeu_pd(lanes, worst);
    *w = std::max({*w, lanes[0], lanes[1]});
    _mm_storeu_pd(lanes, extent);
    *e = std::max({*e, lanes[0], lanes[1]});
    _mm_storeu_pd(lanes, worst2);
    *w2 = std::max({*w2, lanes[0], lanes[1]});
  }
};

// In 2D a particle is one SSE2 vector: the scalar loop's operations lane by lane (no fused
// multiply-add in either), so the same bits; two particles a time give their ‖·‖² as one vector
// (each the scalar sum dd₀² + dd₁²). Maxima are taken as max(new, kept), which keeps `kept` when
// new is NaN, as std::max(kept, new) does. The slots [begin, end) two at a time; returns the first
// slot left for the scalar loop.
template <bool Noise, bool Trap, bool Active, bool Bound>
[[gnu::always_inline]] inline int PredictPairs2(const PlainConstants& k,
                                                const double* __restrict xs,
                                                const double* __restrict act,
                                                const double* __restrict rs, double* __restrict ys,
                                                const double* xi, int begin, int end, Maxima2* m,
                                                std::int64_t* far, bool* nonfinite) {
  const __m128d neg_g = _mm_set1_pd(-k.g), hv = _mm_set1_pd(k.h), sv = _mm_set1_pd(k.sigma);
  const __m128d cv = _mm_set_pd(k.c[1], k.c[0]),
                big = _mm_set1_pd(std::numeric_limits<double>::max());
  const __m128d sign = _mm_set1_pd(-0.0), r2v = _mm_set1_pd(k.reach2);
  int flags = 0;
  // Y of slot s stored; returns (Y − X)² and sets *e2 to (Y − R)² (Bound), *abs to |Y|.
  auto one = [&](int s, __m128d* e2, __m128d* abs) {
    const __m128d xv = _mm_loadu_pd(xs + 2 * s);
    __m128d v = Trap ? _mm_mul_pd(neg_g, _mm_sub_pd(xv, cv)) : _mm_setzero_pd();
    if constexpr (Active) v = _mm_add_pd(v, _mm_loadu_pd(act + 2 * s));
    __m128d yv = _mm_add_pd(xv, _mm_mul_pd(hv, v));
    if constexpr (Noise) {
      const int i = s - begin;
      yv = _mm_add_pd(yv, _mm_mul_pd(sv, _mm_set_pd(xi[kNoiseBatch + i], xi[i])));
    }
    _mm_storeu_pd(ys + 2 * s, yv);
    *abs = _mm_andnot_pd(sign, yv);
    flags |= _mm_movemask_pd(_mm_cmpnle_pd(*abs, big));
    if constexpr (Bound) {
      const __m128d e = _mm_sub_pd(yv, _mm_loadu_pd(rs + 2 * s));
      *e2 = _mm_mul_pd(e, e);
    }
    const __m128d d = _mm_sub_pd(yv, xv);
    return _mm_mul_pd(d, d);
  };
  int first = begin;
  for (; first + 2 <= end; first += 2) {
    __m128d e2a = _mm_setzero_pd(), e2b = _mm_setzero_pd(), abs_a, abs_b;
    const __m128d d2a = one(first, &e2a, &abs_a);
    const __m128d d2b = one(first + 1, &e2b, &abs_b);
    const __m128d d2 = _mm_add_pd(_mm_unpacklo_pd(d2a, d2b), _mm_unpackhi_pd(d2a, d2b));
    m->worst = _mm_max_pd(d2, m->worst);
    m->extent = _mm_max_pd(_mm_max_pd(abs_a, abs_b), m->extent);
    if constexpr (Bound) {
      const __m128d e2 = _mm_add_pd(_mm_unpacklo_pd(e2a, e2b), _mm_unpackhi_pd(e2a, e2b));
      m->worst2 = _mm_max_pd(e2, m->worst2);
      const int over = _mm_movemask_pd(_mm_cmpgt_pd(e2, r2v));
      *far += (over & 1) + (over >> 1);
    }
  }
  *nonfinite = flags != 0;
  return first;
}
#endif

}  // namespace

bool Prediction::Plain() const {
  const DriftParameters& d = parameters_;
  bool wraps = false;
  for (int a = 0; a < box_.k; ++a) wraps = wraps || (box_.periodic[a] && d.trap);
  return !d.any_constant && !d.propulsion && force_.empty() && uniform_mobility_ && !wraps;
}

template <int K, bool Noise, bool Trap, bool Active, bool Bound>
void Prediction::PredictPlain(const double* x, double* y, const int* id, const std::int64_t* key,
                              const double* active, std::int64_t step, int threads,
                              double* max_move, std::int64_t* bad_id, double* max_coordinate,
                              ExactBound* bound) const {
  const double gamma = parameters_.gamma, sigma = parameters_.sigma, h = h_;
  double center[K];
  for (int a = 0; a < K; ++a) center[a] = parameters_.center[a];
  const std::uint64_t seed = seed_;
  const int n = n_;
  const double* ref = Bound ? bound->reference : nullptr;
  const double quarter2 = Bound ? bound->quarter2 : 0.0;
  auto rows = [&](int begin, int end, [[maybe_unused]] const double* xi, PredictionTotals* t) {
    // PredictImpl's expressions: F = −γ (x − c) (or 0), v = F, y = x + h v (+ σ ξ). Four
    // independent running maxima (lanes), so that no chain of dependent max operations paces the
    // loop; a maximum is exact, so the lanes do not change the result.
    // The constants copied into the loop body and y restrict-qualified: no store to y can
    // change them, so they stay in registers.
    constexpr int kLanes = 4;
    double lane_worst[kLanes] = {}, lane_extent[kLanes] = {}, lane_worst2[kLanes] = {};
    std::int64_t batch_far = 0;
    bool nonfinite = false;
    const double g = gamma, step_h = h, noise_scale = sigma, reach2 = quarter2;
    double c[K];
    for (int a = 0; a < K; ++a) c[a] = center[a];
    const double* __restrict xs = x;
    const double* __restrict rs = ref;
    const double* __restrict as = active;
    double* __restrict ys = y;
    auto row = [&](int s, int l) {
      double d2 = 0.0, e2 = 0.0, far = 0.0;
      for (int a = 0; a < K; ++a) {
        const double xa = xs[K * s + a];
        double v = Trap ? -g * (xa - c[a]) : 0.0;
        if constexpr (Active) v += as[K * s + a];
        double ya = xa + step_h * v;
        if constexpr (Noise) ya += noise_scale * xi[a * kNoiseBatch + (s - begin)];
        ys[K * s + a] = ya;
        nonfinite |= !(std::abs(ya) <= std::numeric_limits<double>::max());
        const double dd = ya - xa;
        d2 += dd * dd;
        far = std::max(far, std::abs(ya));
        if constexpr (Bound) {
          const double de = ya - rs[K * s + a];
          e2 += de * de;
        }
      }
      lane_worst[l] = std::max(lane_worst[l], d2);
      lane_extent[l] = std::max(lane_extent[l], far);
      if constexpr (Bound) {
        lane_worst2[l] = std::max(lane_worst2[l], e2);
        batch_far += e2 > reach2 ? 1 : 0;
      }
    };
    int first = begin;
#if defined(__SSE2__)
    [[maybe_unused]] Maxima2 vec;
    if constexpr (K == 2) {
      first = PredictPairs2<Noise, Trap, Active, Bound>(
          {g, step_h, noise_scale, reach2, {c[0], c[1]}}, xs, as, rs, ys, xi, begin, end, &vec,
          &batch_far, &nonfinite);
    }
#endif
    for (; first + kLanes <= end; first += kLanes) {
      for (int l = 0; l < kLanes; ++l) row(first + l, l);
    }
    for (; first < end; ++first) row(first, 0);
    double batch_worst = 0.0, batch_extent = 0.0, batch_worst2 = 0.0;
    for (int l = 0; l < kLanes; ++l) {
      batch_worst = std::max(batch_worst, lane_worst[l]);
      batch_extent = std::max(batch_extent, lane_extent[l]);
      batch_worst2 = std::max(batch_worst2, lane_worst2[l]);
    }
#if defined(__SSE2__)
    if constexpr (K == 2) vec.Fold(&batch_worst, &batch_extent, &batch_worst2);
#endif
    std::int64_t batch_bad = std::numeric_limits<std::int64_t>::max();
    if (nonfinite) {
      batch_bad = RescanFinite<K>(x, y, id, begin, end, &batch_worst, &batch_extent);
    }
    *t = {batch_worst, batch_extent, batch_worst2, batch_bad, batch_far};
  };
  ReportPrediction(OverNoiseBatches<K, Noise>(n, threads, seed, key, id, step, rows), max_move,
                   bad_id, max_coordinate, bound);
}

void Prediction::PredictPlainDispatch(const double* x, double* y, const int* id,
                                      const std::int64_t* key, const double* active,
                                      std::int64_t step, int threads, double* max_move,
                                      std::int64_t* bad_id, double* max_coordinate,
                                      ExactBound* bound) const {
  auto pick = [](bool b, auto f) {
    if (b) {
      f(std::true_type{});
    } else {
      f(std::false_type{});
    }
  };
  DispatchDimension(box_.k, [&](auto k) {
    if constexpr (k > 1) {
      pick(parameters_.sigma > 0.0, [&](auto noise) {
        pick(parameters_.trap, [&](auto trap) {
          pick(active != nullptr, [&](auto act) {
            pick(bound != nullptr, [&](auto b) {
              PredictPlain<k, noise, trap, act, b>(x, y, id, key, active, step, threads, max_move,
                                                   bad_id, max_coordinate, bound);
            });
          });
        });
      });
    }
  });
}

}  // namespace moreau::particles::internal
