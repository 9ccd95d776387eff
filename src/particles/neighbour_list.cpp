#include "particles/neighbour_list.h"

#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "particles/parallel.h"

namespace moreau::particles::internal {

void NeighbourList::Configure(const PeriodicBox& box, int n, double skin, double skin_limit,
                              double attraction_range) {
  box_ = box;
  n_ = n;
  nominal_skin_ = skin;
  skin_limit_ = skin_limit;
  skin_ = std::min(skin, skin_limit);
  attraction_range_ = attraction_range;
  row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  reference_.assign(static_cast<std::size_t>(box.k) * static_cast<std::size_t>(n), 0.0);
}

double NeighbourList::BoundAfterPrediction(double step_move, const double* y, int threads,
                                           const ExactBound* fused) {
  // max_i ‖Y_i − X_i^build‖ ≤ (bound on ‖X_i − X_i^build‖) + max_i ‖Y_i − X_i‖: a bound without
  // reading the build positions; only when it reaches skin/4 is the exact maximum computed.
  const double moved = drift_bound_ + step_move;
  far_slots_ = std::numeric_limits<std::int64_t>::max();
  if (!(moved > 0.25 * skin_)) return moved;
  if (fused != nullptr) {
    MOREAU_ASSERT(fused->reference == reference_.data() &&
                  fused->quarter2 == 0.0625 * skin_ * skin_);
    far_slots_ = fused->far;
    return std::sqrt(fused->worst2);
  }
  const double* r0 = reference_.data();
  const int k = box_.k;
  const std::int64_t n = n_;
  const double quarter2 = 0.0625 * skin_ * skin_;
  double worst = 0.0;
  std::int64_t far = 0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst) \
    reduction(+ : far)
  for (std::int64_t s = 0; s < n; ++s) {
    double d2 = 0.0;
    for (int a = 0; a < k; ++a) {
      const double d = y[k * s + a] - r0[k * s + a];
      d2 += d * d;
    }
    worst = std::max(worst, d2);
    if (d2 > quarter2) ++far;
  }
  far_slots_ = far;
  return std::sqrt(worst);
}

bool NeighbourList::Accept(double moved) {
  const double accept = 0.5 * skin_ * (1.0 - 1e-9);
  if (!(moved * (1.0 + 1e-12) < accept)) return false;
  drift_bound_ = moved * (1.0 + 1e-12);  // bounds ‖X_i − X_i^build‖ after the step
  return true;
}

bool NeighbourList::Listed(int s, int t) const {
  const int a = std::min(s, t), b = std::max(s, t);
  const int* row = nbr_.data();
  for (int p = row_start_[static_cast<std::size_t>(a)];
       p < row_start_[static_cast<std::size_t>(a) + 1]; ++p) {
    if (row[p] == b) return true;
  }
  return false;
}

// Slot f (fast) and every slot t with a build position within 2 cells of f's are a pair of the
// list or were apart at the build by more than their contact distance plus both bounds (the
// minimum image on periodic axes). Slots farther away are ≥ 2 min edge apart (AcceptEach).
template <int K>
bool NeighbourList::LocalPairsApart(int f, const CellList& cells, const int* members,
                                    const double* radius) const {
  const double* rf = reference_.data() + static_cast<std::ptrdiff_t>(K) * f;
  const double bf = bound_[static_cast<std::size_t>(f)];
  bool apart = true;
  auto check = [&](int t) {
    if (t == f || !apart) return;
    double d2 = 0.0;
    for (int a = 0; a < K; ++a) {
      double u = rf[a] - reference_[static_cast<std::size_t>(K * t + a)];
      if (box_.periodic[a]) u -= box_.len[a] * std::nearbyint(u / box_.len[a]);
      d2 += u * u;
    }
    const double contact =
        radius[f] + radius[t] + attraction_range_ + bf + bound_[static_cast<std::size_t>(t)];
    if (!(std::sqrt(d2) * (1.0 - 1e-12) > contact) && !Listed(f, t)) apart = false;
  };
  cells.grid().ForEachCellWithin<K>(rf, 2, [&](std::int64_t cell) {
    const std::int64_t rank = cells.rank(cell);
    for (std::int64_t q = cells.cell_start(rank); q < cells.cell_start(rank + 1); ++q) {
      check(members != nullptr ? members[q] : static_cast<int>(q));
    }
  });
  return apart;
}

bool NeighbourList::AcceptEach(const double* start, const double* x, const double* radius,
                               const std::vector<double>& path, const CellList& cells,
                               const int* members, int threads) {
  const int k = box_.k;
  const std::int64_t n = n_;
  const double half = 0.5 * skin_;
  bound_.resize(static_cast<std::size_t>(n));
  double* b = bound_.data();
  const double* r0 = reference_.data();
  double largest = 0.0;  // the largest bound
  double end = 0.0;      // max_s ‖x_s − X_s^build‖
  double rmax = 0.0;
  std::int64_t fast_count = 0;
#pragma omp parallel for num_threads(threads) schedule(static) \
    reduction(max : largest, end, rmax) reduction(+ : fast_count)
  for (std::int64_t s = 0; s < n; ++s) {
    double e2 = 0.0, f2 = 0.0;
    for (int a = 0; a < k; ++a) {
      const double d = start[k * s + a] - r0[k * s + a];
      const double f = x[k * s + a] - r0[k * s + a];
      e2 += d * d;
      f2 += f * f;
    }
    const double to_end = std::sqrt(f2);
    end = std::max(end, to_end);
    rmax = std::max(rmax, radius[s]);
    // A point P on a path of length L from A to B has |P − A| + |P − B| ≤ L, so
    // |P − X^build| ≤ (|A − X^build| + |B − X^build| + L) / 2.
    b[s] = 0.5 * (std::sqrt(e2) + to_end + path[static_cast<std::size_t>(s)]) * (1.0 + 1e-12);
    largest = std::max(largest, b[s]);
    if (b[s] >= half) ++fast_count;
  }
  // Two slots left out of the list stay apart when b_s + b_t < skin: every pair of slow slots;
  // pairs more than 2 cells apart are ≥ 2 min edge apart at the build.
  double edge = std::numeric_limits<double>::infinity();
  for (int a = 0; a < k; ++a) edge = std::min(edge, cells.grid().edge[a]);
  const double room = skin_ * (1.0 - 1e-9);
  if (fast_count > std::max<std::int64_t>(kMaxFastSlots, n / 16) || !(largest < room) ||
      !(2.0 * largest < (2.0 * edge - 2.0 * rmax - attraction_range_) * (1.0 - 1e-9))) {
    return false;
  }
  for (int f = 0; f < n_; ++f) {
    if (bound_[static_cast<std::size_t>(f)] < half) continue;
    const bool apart = k == 2 ? LocalPairsApart<2>(f, cells, members, radius)
                              : (k == 3 ? LocalPairsApart<3>(f, cells, members, radius)
                                        : LocalPairsApart<1>(f, cells, members, radius));
    if (!apart) return false;
  }
  drift_bound_ = end * (1.0 + 1e-12);  // bounds ‖X_i − X_i^build‖ after the step
  return true;
}

bool NeighbourList::PrepareRedo() {
  if (!built_here_) return true;
  if (skin_ >= skin_limit_) return false;
  skin_ = std::min(2.0 * skin_, skin_limit_);
  return true;
}

LexicographicPairList::LexicographicPairList(const PeriodicBox& box, int n, double max_radius,
                                             double skin)
    : box_(box), reach_(2.0 * max_radius + skin), id_(static_cast<std::size_t>(n)) {
  list_.Configure(box, n, skin, std::numeric_limits<double>::infinity(), 0.0);
  for (int i = 0; i < n; ++i) id_[static_cast<std::size_t>(i)] = i;
}

void LexicographicPairList::Build(const double* x, const double* radius) {
  const int n = static_cast<int>(id_.size());
  cells_.Fit(x, n, box_, reach_, 0, 1);
  cells_.Sort(x, id_.data(), n, 1);
  list_.Build(x, radius, cells_, cells_.permutation().data(), ListRows::kSorted, 0, 1);
}

namespace {

template <int K, bool P>
double MaxPairOverlapImpl(const NeighbourList& list, const double* x, const double* radius, int n,
                          int threads) {
  // The non-empty rows only (an empty row's overlap is 0).
  MOREAU_ASSERT(list.active_rows_end() - list.active_rows() <= n);
  const int* rows = list.active_rows();
  double worst = 0.0;
  ParallelForMax(threads, 0, list.active_rows_end() - rows, &worst,
                 [&](std::int64_t i) { return list.RowOverlap<K, P>(x, radius, rows[i]); });
  return worst;
}

}  // namespace

double MaxPairOverlap(const NeighbourList& list, const double* x, const double* radius, int n,
                      int threads) {
  return DispatchDimensionPeriodic(list.box().k, list.box().any, [&](auto kk, auto p) {
    return MaxPairOverlapImpl<kk, p>(list, x, radius, n, threads);
  });
}

}  // namespace moreau::particles::internal
