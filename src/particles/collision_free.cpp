// The collision-free speed model's velocities (forces.h CollisionFreeSpeed): repulsions, walking
// directions, headways and speeds at the current positions, per slot, before the prediction.
#include <algorithm>
#include <cmath>
#include <limits>

#include "particles/parallel.h"
#include "particles/prediction.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

namespace {

// The walls' and segments' repulsion Σ_w a_w exp((ℓ/2 − d_iw) / D_w) n_iw at x (2D) added to rep.
void AddWallRepulsion(const CollisionFreeSpeed& m, const ParticleModel& model, const double* x,
                      double* rep) {
  const double half = 0.5 * m.length;
  for (const Wall& w : model.walls) {
    const double norm = std::hypot(w.normal[0], w.normal[1]);
    const double n0 = w.normal[0] / norm, n1 = w.normal[1] / norm;
    const double d = n0 * x[0] + n1 * x[1] - w.offset / norm;
    const double weight = m.wall_repulsion * std::exp((half - d) / m.wall_repulsion_range);
    rep[0] += weight * n0;
    rep[1] += weight * n1;
  }
  for (const SegmentObstacle& g : model.segments) {
    const double ab0 = g.b[0] - g.a[0], ab1 = g.b[1] - g.a[1];
    const double t = std::clamp(
        ((x[0] - g.a[0]) * ab0 + (x[1] - g.a[1]) * ab1) / (ab0 * ab0 + ab1 * ab1), 0.0, 1.0);
    const double u0 = x[0] - (g.a[0] + t * ab0), u1 = x[1] - (g.a[1] + t * ab1);
    const double d = std::hypot(u0, u1);
    if (!(d > 0.0)) continue;
    const double weight = m.wall_repulsion * std::exp((half - d) / m.wall_repulsion_range) / d;
    rep[0] += weight * u0;
    rep[1] += weight * u1;
  }
}

// Whether a neighbour at displacement u = x_j − x_i lies in the path of a person walking along e
// (2D): ahead, ⟨e, u⟩ > 0, and within the body length ℓ of the line of walking.
inline bool InPath(const double* e, const double* u, double length) {
  return e[0] * u[0] + e[1] * u[1] > 0.0 && std::abs(e[0] * u[1] - e[1] * u[0]) < length;
}

}  // namespace

template <int K, bool P>
void Prediction::CollisionFreeWalkImpl(const StepContext& context) {
  static_assert(K == 2, "the collision-free speed model is two-dimensional");
  const ParticleStore& store = *context.store;
  const double* x = store.current.data();
  const int* id = store.id.data();
  const std::int64_t* key = store.noise_key.empty() ? nullptr : store.noise_key.data();
  const DriftParameters& d = parameters_;
  const CollisionFreeSpeed& m = d.walk;
  const double range = CollisionFreeRange(m, d.v0 + 3.0 * d.speed_sd);
  const double range2 = range * range;
  const NeighbourList& list = context.list;
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  double* w = walk_.data();
  double* headway = headway_.data();
  std::fill(walk_.begin(), walk_.end(), 0.0);
  // Over the list's pairs closer than R: the repulsion (pass 0), or the headways (pass 1).
  int pass = 0;
  auto rows = [&](int begin, int end) {
    for (int s = begin; s < end; ++s) {
      for (std::int64_t p = row_start[s]; p < row_start[s + 1]; ++p) {
        const int t = nbr[p];
        double u[K];  // x_s − x_t
        list.Displacement<K, P>(x, s, t, p, u);
        const double r2 = SquaredNorm<K>(u);
        if (!(r2 < range2) || r2 == 0.0) continue;
        const double r = std::sqrt(r2);
        if (pass == 0) {
          const double g = m.repulsion * std::exp((m.length - r) / m.repulsion_range) / r;
          for (int a = 0; a < K; ++a) {
            w[K * s + a] += g * u[a];
            w[K * t + a] -= g * u[a];
          }
          continue;
        }
        const double ahead[K] = {-u[0], -u[1]};  // x_t − x_s
        if (InPath(w + K * s, ahead, m.length)) headway[s] = std::min(headway[s], r);
        if (InPath(w + K * t, u, m.length)) headway[t] = std::min(headway[t], r);
      }
    }
  };
  const auto over_pairs = [&] {
    if (context.lexicographic) {
      rows(0, n_);
      return;
    }
#pragma omp parallel num_threads(context.threads)
    ForEachBlockByColour(context.colouring, context.cells, rows);
  };
  over_pairs();
  const bool wrap = box_.any;
  ParallelFor(context.threads, 0, n_, [&](std::int64_t i) {
    const auto s = static_cast<int>(i);
    double xw[K];
    for (int a = 0; a < K; ++a) {
      xw[a] = x[K * s + a];
      if (wrap && box_.periodic[a]) xw[a] = Wrap(xw[a], box_.lo[a], box_.len[a]);
    }
    double e[K];
    DesiredDirection<K>(d, xw, e);
    double* u = w + K * s;
    AddWallRepulsion(m, context.model, xw, u);
    for (int a = 0; a < K; ++a) u[a] += e[a];
    const double norm = std::sqrt(SquaredNorm<K>(u));
    for (int a = 0; a < K; ++a) u[a] = norm > 0.0 ? u[a] / norm : 0.0;
    headway[s] = std::numeric_limits<double>::infinity();
  });
  pass = 1;
  over_pairs();
  ParallelFor(context.threads, 0, n_, [&](std::int64_t i) {
    const auto s = static_cast<int>(i);
    const double v0 = DesiredSpeed(seed_, key != nullptr ? key[s] : id[s], d.v0, d.speed_sd);
    const double speed = CollisionFreeSpeedAt(m, v0, headway[s]);
    for (int a = 0; a < K; ++a) w[K * s + a] *= speed;
  });
}

void Prediction::CollisionFreeWalk(const StepContext& context) {
  if (box_.any) {
    CollisionFreeWalkImpl<2, true>(context);
  } else {
    CollisionFreeWalkImpl<2, false>(context);
  }
}

}  // namespace moreau::particles::internal
