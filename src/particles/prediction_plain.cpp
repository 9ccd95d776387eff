// The prediction's loop for a drift of at most the trap (Prediction::Plain): no branches, the
// general loop's arithmetic (prediction.cpp), tested bit for bit against it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "particles/noise.h"
#include "particles/prediction.h"

namespace moreau::particles::internal {

bool Prediction::Plain(const double* active) const {
  const DriftParameters& d = parameters_;
  bool wraps = false;
  for (int a = 0; a < box_.k; ++a) wraps = wraps || (box_.periodic[a] && d.trap);
  return !d.any_constant && !d.propulsion && force_.empty() && uniform_mobility_ &&
         active == nullptr && !wraps;
}

template <int K, bool Noise, bool Trap, bool Bound>
void Prediction::PredictPlain(const double* x, double* y, const int* id, const std::int64_t* key,
                              std::int64_t step, int threads, double* max_move,
                              std::int64_t* bad_id, double* max_coordinate,
                              ExactBound* bound) const {
  const double gamma = parameters_.gamma, sigma = parameters_.sigma, h = h_;
  double center[K];
  for (int a = 0; a < K; ++a) center[a] = parameters_.center[a];
  const std::uint64_t seed = seed_;
  const int n = n_;
  const double* ref = Bound ? bound->reference : nullptr;
  const double quarter2 = Bound ? bound->quarter2 : 0.0;
  double worst = 0.0, extent = 0.0, worst2 = 0.0;
  std::int64_t bad = std::numeric_limits<std::int64_t>::max(), far_count = 0;
  const int batches = (n + kNoiseBatch - 1) / kNoiseBatch;
#pragma omp parallel for num_threads(threads) schedule(static) \
    reduction(max : worst, extent, worst2) reduction(min : bad) reduction(+ : far_count)
  for (int batch = 0; batch < batches; ++batch) {
    const int begin = batch * kNoiseBatch;
    const int end = std::min(n, begin + kNoiseBatch);
    [[maybe_unused]] double xi[3 * kNoiseBatch];
    if constexpr (Noise) BatchNoise<K>(seed, key, id, step, begin, end, xi);
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
    double* __restrict ys = y;
    auto row = [&](int s, int l) {
      double d2 = 0.0, e2 = 0.0, far = 0.0;
      for (int a = 0; a < K; ++a) {
        const double xa = xs[K * s + a];
        const double v = Trap ? -g * (xa - c[a]) : 0.0;
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
    const bool finite = !nonfinite;
    if (!finite) {  // the batch's finite rows only, as PredictImpl
      batch_worst = batch_extent = 0.0;
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
          batch_worst = std::max(batch_worst, d2);
          batch_extent = std::max(batch_extent, far);
        }
      }
    }
    worst = std::max(worst, batch_worst);
    extent = std::max(extent, batch_extent);
    worst2 = std::max(worst2, batch_worst2);
    far_count += batch_far;
  }
  *max_move = std::sqrt(worst);
  if (max_coordinate != nullptr) *max_coordinate = extent;
  *bad_id = bad == std::numeric_limits<std::int64_t>::max() ? -1 : bad;
  if constexpr (Bound) {
    bound->worst2 = worst2;
    bound->far = far_count;
  }
}

void Prediction::PredictPlainDispatch(const double* x, double* y, const int* id,
                                      const std::int64_t* key, std::int64_t step, int threads,
                                      double* max_move, std::int64_t* bad_id,
                                      double* max_coordinate, ExactBound* bound) const {
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
          pick(bound != nullptr, [&](auto b) {
            PredictPlain<k, noise, trap, b>(x, y, id, key, step, threads, max_move, bad_id,
                                            max_coordinate, bound);
          });
        });
      });
    }
  });
}

}  // namespace moreau::particles::internal
