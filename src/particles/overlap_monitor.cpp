#include "particles/overlap_monitor.h"

#include <algorithm>
#include <cmath>

#include "particles/parallel.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

namespace {

constexpr std::size_t kRowsPerTeam = 16384;  // fewer near rows are measured on one thread

// The largest overlap over the pairs of the given rows, computed as MaxPairOverlap does.
template <int K, bool P>
double RowsOverlap(const NeighbourList& list, const double* x, const double* radius,
                   const std::vector<int>& rows) {
  double worst = 0.0;
  for (const int s : rows) worst = std::max(worst, list.RowOverlap<K, P>(x, radius, s));
  return worst;
}

}  // namespace

NearContactRows* OverlapMonitor::Prepare(int threads) {
  near_.rows.resize(static_cast<std::size_t>(std::max(1, threads)));
  for (std::vector<int>& r : near_.rows) r.clear();
  near_.margin = margin_;
  near_.max_path = 0.0;
  prepared_ = true;
  return &near_;
}

double OverlapMonitor::Measure(const StepContext& context, double max_coordinate) {
  const NeighbourList& list = context.list;
  const double* x = context.store->current.data();
  const double* radius = context.store->radius.data();
  const int threads = context.threads;
  const PeriodicBox& box = list.box();
  double scale = max_coordinate + near_.max_path + 2.0 * context.rmax + list.skin();
  for (int a = 0; a < box.k; ++a) scale += box.len[a];
  const double slack = 0x1.0p-30 * scale;
  const double path = near_.max_path;
  // No move at all (path 0): every pair kept its visited distance, so the recorded rows (margin
  // ≥ 0) hold every overlap.
  const bool screened = prepared_ && (path == 0.0 || 2.0 * path + slack <= near_.margin);
  double worst = 0.0;
  if (screened) {
    const int lists = static_cast<int>(near_.rows.size());
    std::size_t rows = 0;
    for (const std::vector<int>& r : near_.rows) rows += r.size();
    // A few rows are measured on this thread: waking a team costs more than they do.
    const int team = rows >= kRowsPerTeam ? threads : 1;
    DispatchDimensionPeriodic(box.k, box.any, [&](auto kk, auto p) {
      ParallelForMax(team, 0, lists, &worst, [&](std::int64_t t) {
        return RowsOverlap<kk, p>(list, x, radius, near_.rows[static_cast<std::size_t>(t)]);
      });
    });
    ++screened_steps_;
  } else {
    worst = MaxPairOverlap(list, x, radius, context.n, threads);
    ++full_steps_;
  }
  if (prepared_) margin_ = std::max(4.0 * path, 0.5 * margin_) + 2.0 * slack;
  prepared_ = false;
  return worst;
}

}  // namespace moreau::particles::internal
