// The collision-free speed model's velocities (forces.h CollisionFreeSpeed): repulsions, walking
// directions, headways and speeds at the current positions, per slot, before the prediction.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "particles/parallel.h"
#include "particles/prediction.h"
#include "particles/segment_grid.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

// exp(z) is +0 for every z < −745.2 (the smallest subnormal is e^−744.4): walls and segments
// farther than ℓ/2 + kZeroExponent D_w contribute exactly +0 and are skipped (the same bits).
constexpr double kZeroExponent = 746.0;
// The per-person pass asks for the routing field's nodes of the person this many slots on: the
// reads of Direction (scattered over a field of tens of MB) then mostly hit the cache.
constexpr int kRouteAhead = 8;

// The walls' and segments' repulsion Σ_w a_w exp((ℓ/2 − d_iw) / D_w) n_iw (2D), the segments
// binned on a grid (segment_grid.h) with the cut-off ℓ/2 + kZeroExponent D_w: a person looks
// only at its cell's segments and adds the same terms in the same order as a loop over all.
class CollisionFreeWalls {
 public:
  CollisionFreeWalls(const CollisionFreeSpeed& m, const ParticleModel& model)
      : a_(m.wall_repulsion),
        range_(m.wall_repulsion_range),
        half_(0.5 * m.length),
        source_walls_(model.walls),
        source_segments_(model.segments) {
    cut_ = half_ + kZeroExponent * range_;
    for (const Wall& w : model.walls) {
      const double norm = std::hypot(w.normal[0], w.normal[1]);
      walls_.push_back({w.normal[0] / norm, w.normal[1] / norm, w.offset / norm});
    }
    for (const SegmentObstacle& g : model.segments) {
      const double ab0 = g.b[0] - g.a[0], ab1 = g.b[1] - g.a[1];
      segments_.push_back({g.a[0], g.a[1], ab0, ab1, ab0 * ab0 + ab1 * ab1});
    }
    grid_ = SegmentGrid::Of(model.segments, cut_, 64);
  }

  // Whether this was built for these parameters and walls (then it can be used again).
  bool Matches(const CollisionFreeSpeed& m, const ParticleModel& model) const {
    const auto same_wall = [](const Wall& p, const Wall& q) {
      return p.normal == q.normal && p.offset == q.offset;
    };
    const auto same_segment = [](const SegmentObstacle& p, const SegmentObstacle& q) {
      return p.a == q.a && p.b == q.b;
    };
    return a_ == m.wall_repulsion && range_ == m.wall_repulsion_range && half_ == 0.5 * m.length &&
           std::equal(model.walls.begin(), model.walls.end(), source_walls_.begin(),
                      source_walls_.end(), same_wall) &&
           std::equal(model.segments.begin(), model.segments.end(), source_segments_.begin(),
                      source_segments_.end(), same_segment);
  }

  // Adds the repulsion at x to rep.
  void Add(const double* x, double* rep) const {
    for (const WallTerm& w : walls_) {
      const double z = (half_ - (w.n0 * x[0] + w.n1 * x[1] - w.offset)) / range_;
      if (z < -kZeroExponent) continue;
      const double weight = a_ * std::exp(z);
      rep[0] += weight * w.n0;
      rep[1] += weight * w.n1;
    }
    grid_.ForEachNear(x, segments_.size(), [&](std::size_t g) {
      AddSegment(segments_[g], x, rep);
      return false;
    });
  }

 private:
  struct WallTerm {
    double n0, n1, offset;  // unit normal, offset / ‖normal‖
  };
  struct SegmentTerm {
    double a0, a1, ab0, ab1, ab2;  // a, b − a, ‖b − a‖²
  };
  void AddSegment(const SegmentTerm& g, const double* x, double* rep) const {
    const double t = std::clamp(((x[0] - g.a0) * g.ab0 + (x[1] - g.a1) * g.ab1) / g.ab2, 0.0, 1.0);
    const double u0 = x[0] - (g.a0 + t * g.ab0), u1 = x[1] - (g.a1 + t * g.ab1);
    if (u0 * u0 + u1 * u1 > cut_ * cut_) return;  // exp's argument below −745.2: +0
    const double d = std::hypot(u0, u1);
    if (!(d > 0.0)) return;
    const double weight = a_ * std::exp((half_ - d) / range_) / d;
    rep[0] += weight * u0;
    rep[1] += weight * u1;
  }

  double a_, range_, half_, cut_ = 0.0;
  std::vector<Wall> source_walls_;
  std::vector<SegmentObstacle> source_segments_;
  std::vector<WallTerm> walls_;
  std::vector<SegmentTerm> segments_;
  SegmentGrid grid_;
};

namespace {

// Whether a neighbour at displacement u = x_j − x_i lies in the path of a person walking along e
// (2D): ahead, ⟨e, u⟩ > 0, and within the body length ℓ of the line of walking, as 1 or 0.
// Both tests are made (& instead of &&), for the pass over pairs to have no branch on them.
inline int InPath(const double* e, const double* u, double length) {
  return static_cast<int>(e[0] * u[0] + e[1] * u[1] > 0.0) &
         static_cast<int>(std::abs(e[0] * u[1] - e[1] * u[0]) < length);
}

constexpr double kNoHeadway = std::numeric_limits<double>::infinity();
// Added to a squared distance: +∞ when the pair is no headway (index 0), else +0, which leaves
// it exact. A load instead of a select: the in-path tests are as good as random, and a branch on
// them was mispredicted about every other pair.
constexpr double kHeadwayOrNone[2] = {kNoHeadway, 0.0};

}  // namespace

// The two passes over the list's pairs closer than R (2D), rows [begin, end): the repulsions
// into w, and later the squared headways along the unit directions then in w. Slot s's own
// entries are kept in registers over its row (t > s in it), in the order of the additions.
template <bool P>
struct CollisionFreePairs {
  const NeighbourList& list;
  const double* x;
  double* w;
  double* headway2;
  const CollisionFreeSpeed& m;
  double range2;

  // In batches of in-range pairs: their distances, then their exponentials (independent calls
  // the processor overlaps), then the additions in the pairs' order. A listed pair out of range
  // (about one in five) is skipped without a branch.
  void Repulsion(int begin, int end) const {
    constexpr int kBatch = 8;
    const int* row_start = list.row_start();
    const int* nbr = list.neighbours();
    for (int s = begin; s < end; ++s) {
      double ws[2] = {w[2 * s], w[2 * s + 1]};
      for (std::int64_t p = row_start[s]; p < row_start[s + 1];) {
        int tb[kBatch];
        double ub[kBatch][2], rb[kBatch], eb[kBatch];
        int nb = 0;
        for (; p < row_start[s + 1] && nb < kBatch; ++p) {
          const int t = nbr[p];
          list.Displacement<2, P>(x, s, t, p, ub[nb]);  // x_s − x_t
          const double r2 = SquaredNorm<2>(ub[nb]);
          // Written whether in range or not, kept by advancing nb: no branch per pair.
          tb[nb] = t;
          rb[nb] = std::sqrt(r2);
          eb[nb] = (m.length - rb[nb]) / m.repulsion_range;
          nb += static_cast<int>(r2 < range2) & static_cast<int>(r2 != 0.0);
        }
        for (int b = 0; b < nb; ++b) eb[b] = std::exp(eb[b]);
        for (int b = 0; b < nb; ++b) {
          const double g = m.repulsion * eb[b] / rb[b];
          for (int a = 0; a < 2; ++a) {
            ws[a] += g * ub[b][a];
            w[2 * tb[b] + a] -= g * ub[b][a];
          }
        }
      }
      w[2 * s] = ws[0];
      w[2 * s + 1] = ws[1];
    }
  }

  // Squared: the square root of their minimum is the minimum of the roots. No branch per pair.
  void Headways(int begin, int end) const {
    const int* row_start = list.row_start();
    const int* nbr = list.neighbours();
    for (int s = begin; s < end; ++s) {
      const double es[2] = {w[2 * s], w[2 * s + 1]};
      double hs = headway2[s];
      for (std::int64_t p = row_start[s]; p < row_start[s + 1]; ++p) {
        const int t = nbr[p];
        double u[2];  // x_s − x_t
        list.Displacement<2, P>(x, s, t, p, u);
        const double r2 = SquaredNorm<2>(u);
        const int near = static_cast<int>(r2 < range2) & static_cast<int>(r2 != 0.0);
        const double ahead[2] = {-u[0], -u[1]};  // x_t − x_s
        hs = std::min(hs, r2 + kHeadwayOrNone[near & InPath(es, ahead, m.length)]);
        const int behind = near & InPath(w + 2 * t, u, m.length);  // s in t's path
        headway2[t] = std::min(headway2[t], r2 + kHeadwayOrNone[behind]);
      }
      headway2[s] = hs;
    }
  }
};

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
  double* w = walk_.data();
  double* headway2 = headway_.data();  // squared until the speeds
  std::fill(walk_.begin(), walk_.end(), 0.0);
  if (walls_ == nullptr || !walls_->Matches(m, context.model)) {
    walls_ = std::make_shared<const CollisionFreeWalls>(m, context.model);
  }
  const CollisionFreeWalls& walls = *walls_;
  const CollisionFreePairs<P> pairs{context.list, x, w, headway2, m, range * range};
  const bool wrap = box_.any;
  const DistanceField* route = d.route;
  // The direction e_s from the repulsions in w (then complete), the walls' and e0.
  const auto direct = [&](int s) {
    if (route != nullptr && !wrap && s + kRouteAhead < n_) {
      const double* node = route->DirectionNodes(x + K * (s + kRouteAhead));
      const std::ptrdiff_t row = route->DirectionRowStride();
      __builtin_prefetch(node);
      __builtin_prefetch(node + 3);
      __builtin_prefetch(node + row);
      __builtin_prefetch(node + row + 3);
    }
    double xw[K];
    for (int a = 0; a < K; ++a) {
      xw[a] = x[K * s + a];
      if (wrap && box_.periodic[a]) xw[a] = Wrap(xw[a], box_.lo[a], box_.len[a]);
    }
    double e[K];
    DesiredDirection<K>(d, xw, e);
    double* u = w + K * s;
    walls.Add(xw, u);
    for (int a = 0; a < K; ++a) u[a] += e[a];
    const double norm = std::sqrt(SquaredNorm<K>(u));
    for (int a = 0; a < K; ++a) u[a] = norm > 0.0 ? u[a] / norm : 0.0;
    headway2[s] = kNoHeadway;
  };
  const auto speed = [&](int s) {
    const double v0 = DesiredSpeed(seed_, key != nullptr ? key[s] : id[s], d.v0, d.speed_sd);
    const double v = CollisionFreeSpeedAt(m, v0, std::sqrt(headway2[s]));
    for (int a = 0; a < K; ++a) w[K * s + a] *= v;
  };
  if (context.lexicographic) {
    pairs.Repulsion(0, n_);
    for (int s = 0; s < n_; ++s) direct(s);
    pairs.Headways(0, n_);
    for (int s = 0; s < n_; ++s) speed(s);
    return;
  }
  // One team: the pair passes in the colouring's dependency order (the additions to a slot in
  // the order of the colours, whatever the thread count), the per-person parts split evenly.
  repulsion_progress_.Start(context.colouring.blocks());
  headway_progress_.Start(context.colouring.blocks());
  InTeam(context.threads, [&] {
    ForEachBlockInDependencyOrder(context.colouring, context.cells, repulsion_progress_,
                                  [&](int begin, int end) { pairs.Repulsion(begin, end); });
#pragma omp barrier
#pragma omp for schedule(static)
    for (int s = 0; s < n_; ++s) direct(s);
    ForEachBlockInDependencyOrder(context.colouring, context.cells, headway_progress_,
                                  [&](int begin, int end) { pairs.Headways(begin, end); });
#pragma omp barrier
#pragma omp for schedule(static)
    for (int s = 0; s < n_; ++s) speed(s);
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
