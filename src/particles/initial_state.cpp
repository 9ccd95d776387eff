// CheckInitialState and RandomSequentialAddition (initial_state.h): the pair searches use the
// particle core's cell grid and its lexicographic pair list.
#include "moreau/particles/initial_state.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "particles/cell_list.h"
#include "particles/neighbour_list.h"
#include "particles/segment_grid.h"

namespace moreau::particles {

namespace {

using internal::UnitWall;
using internal::UnitWalls;

// The displacement X_i − X_j with the minimum image on periodic axes.
void Displacement(const ParticleModel& model, const double* xi, const double* xj, double* u) {
  for (int a = 0; a < model.dimension; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    u[a] = xi[a] - xj[a];
    if (model.periodic[ua]) {
      u[a] = internal::MinimumImage(u[a], model.domain_hi[ua] - model.domain_lo[ua]);
    }
  }
}

double Norm(int k, const double* u) {
  double r2 = 0.0;
  for (int a = 0; a < k; ++a) r2 += u[a] * u[a];
  return std::sqrt(r2);
}

// The model's segments binned for FixedSetViolation (2D, more than a few): every segment that
// a particle with gap < −tol·r (distance < (1 − tol) r ≤ reach) can reach is listed for it.
internal::SegmentGrid NearSegments(const ParticleModel& model, double tol) {
  if (model.dimension != 2) return {};
  return internal::SegmentGrid::Of(model.segments, model.max_radius() * std::max(1.0, 1.0 - tol),
                                   64);
}

// How deep particle i at x is inside a wall or obstacle (> tol·r_i), as a message; empty if not.
// The segments visited are those `near` lists for x (all when it is not active), in index order:
// a segment it leaves out is farther than the reach, so the answer is the loop over all's.
std::string FixedSetViolation(const ParticleModel& model, const std::vector<UnitWall>& walls,
                              const internal::SegmentGrid& near, int i, const double* x,
                              double tol) {
  const int k = model.dimension;
  const double r = model.radius[static_cast<std::size_t>(i)];
  for (std::size_t w = 0; w < walls.size(); ++w) {
    double g = -walls[w].b - r;
    for (int a = 0; a < k; ++a) g += walls[w].n[a] * x[a];
    if (g < -tol * r) return fmt::format("particle {} is inside walls[{}] by {}", i, w, -g);
  }
  for (std::size_t s = 0; s < model.spheres.size(); ++s) {
    double d[3];
    for (int a = 0; a < k; ++a) d[a] = x[a] - model.spheres[s].center[static_cast<std::size_t>(a)];
    const double g = Norm(k, d) - model.spheres[s].radius - r;
    if (g < -tol * r) return fmt::format("particle {} is inside spheres[{}] by {}", i, s, -g);
  }
  std::string violation;
  near.ForEachNear(x, model.segments.size(), [&](std::size_t s) {
    const double g =
        internal::SegmentGap(x, model.segments[s].a.data(), model.segments[s].b.data(), r);
    if (g < -tol * r) violation = fmt::format("particle {} is inside segments[{}] by {}", i, s, -g);
    return !violation.empty();
  });
  return violation;
}

// Positions wrapped into the periodic domain.
std::vector<double> WrappedCopy(const ParticleModel& model, std::span<const double> positions) {
  std::vector<double> x(positions.begin(), positions.end());
  internal::PeriodicBox::Of(model).WrapAll(x.data(), model.count());
  return x;
}

// Throws InputError for the first pair of the list, in lexicographic order, that overlaps by
// more than tol · (r_i + r_j) (slots are ids).
void CheckPairOverlaps(const ParticleModel& model, const std::vector<double>& x, double tol,
                       const internal::NeighbourList& list) {
  const int k = model.dimension;
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  for (int i = 0; i < model.count(); ++i) {
    const double* xi = &x[static_cast<std::size_t>(k * i)];
    for (int p = row_start[i]; p < row_start[i + 1]; ++p) {
      const int j = nbr[p];
      double u[3];
      Displacement(model, xi, &x[static_cast<std::size_t>(k * j)], u);
      const double c =
          model.radius[static_cast<std::size_t>(i)] + model.radius[static_cast<std::size_t>(j)];
      const double overlap = c - Norm(k, u);
      if (overlap > tol * c) {
        throw InputError(fmt::format(
            "initial state: particles {} and {} overlap by {} (fix it with FixOverlaps / "
            "--fix-overlaps)",
            i, j, overlap));
      }
    }
  }
}

}  // namespace

void CheckInitialState(const ParticleModel& model, std::span<const double> positions, double tol) {
  model.Validate();
  const int k = model.dimension;
  const int n = model.count();
  if (positions.size() != static_cast<std::size_t>(k) * static_cast<std::size_t>(n)) {
    throw InputError(fmt::format("initial state: positions have {} entries for {} particles in {}D",
                                 positions.size(), n, k));
  }
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < k; ++a) {
      if (!std::isfinite(positions[static_cast<std::size_t>(k * i + a)])) {
        throw InputError(fmt::format("initial state: position of particle {} is not finite", i));
      }
    }
  }
  const std::vector<UnitWall> walls = UnitWalls(model);
  const internal::SegmentGrid near = NearSegments(model, tol);
  for (int i = 0; i < n; ++i) {
    const std::string v =
        FixedSetViolation(model, walls, near, i, &positions[static_cast<std::size_t>(k * i)], tol);
    if (!v.empty()) throw InputError("initial state: " + v);
  }
  const std::vector<double> x = WrappedCopy(model, positions);
  // The candidate pairs of the particle core's neighbour list with a small skin (every pair
  // closer than contact is in it), then the exact test on each.
  const double rmax = model.max_radius();
  internal::LexicographicPairList pairs(internal::PeriodicBox::Of(model), n, rmax, 0.01 * rmax);
  pairs.Build(x.data(), model.radius.data());
  CheckPairOverlaps(model, x, tol, pairs.list());
}

namespace {

// The placement box of random sequential addition: [lo, hi] on non-periodic axes (checked), the
// model's domain on periodic ones.
void PlacementBox(const ParticleModel& model, const Vec3& lo, const Vec3& hi, Vec3* glo,
                  Vec3* ghi) {
  *glo = lo;
  *ghi = hi;
  for (int a = 0; a < model.dimension; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (model.periodic[ua]) {
      (*glo)[ua] = model.domain_lo[ua];
      (*ghi)[ua] = model.domain_hi[ua];
    } else if (!(lo[ua] <= hi[ua]) || !std::isfinite(lo[ua]) || !std::isfinite(hi[ua])) {
      throw InputError(
          fmt::format("initial box on axis {} needs lo ≤ hi (got [{}, {}])", a, lo[ua], hi[ua]));
    }
  }
}

// Random sequential addition: the placed particles linked per cell of the particle core's grid
// (edge ≥ 2 max r), each new centre drawn until it is clear of the walls, obstacles and the
// particles in the adjacent cells.
class SequentialPlacement {
 public:
  SequentialPlacement(const ParticleModel& model, const Vec3& lo, const Vec3& hi,
                      std::uint64_t seed)
      : model_(model),
        k_(model.dimension),
        walls_(UnitWalls(model)),
        near_(NearSegments(model, 0.0)),
        rng_(seed) {
    PlacementBox(model, lo, hi, &lo_, &hi_);
    const int n = model.count();
    grid_.Fit(k_, lo_.data(), hi_.data(), internal::PeriodicBox::Of(model),
              2.0 * model.max_radius(), 4 * static_cast<std::int64_t>(n));
    head_.assign(static_cast<std::size_t>(grid_.cells()), -1);
    next_.assign(static_cast<std::size_t>(n), -1);
    x_.assign(static_cast<std::size_t>(k_) * static_cast<std::size_t>(n), 0.0);
  }

  // Places particle i (after 0 … i − 1) in at most max_attempts draws.
  void Place(int i, std::int64_t max_attempts) {
    double* xi = &x_[static_cast<std::size_t>(k_ * i)];
    bool placed = false;
    for (std::int64_t attempt = 0; attempt < max_attempts && !placed; ++attempt) {
      Draw(i, xi);
      placed = FixedSetViolation(model_, walls_, near_, i, xi, 0.0).empty() && ClearOfOthers(i, xi);
    }
    if (!placed) {
      throw InputError(fmt::format(
          "could not place particle {} without overlap in {} attempts (placed {} of {})", i,
          max_attempts, i, model_.count()));
    }
    const std::int64_t cell = grid_.CellOf(xi);
    next_[static_cast<std::size_t>(i)] = head_[static_cast<std::size_t>(cell)];
    head_[static_cast<std::size_t>(cell)] = i;
  }

  std::vector<double> Take() { return std::move(x_); }

 private:
  // A centre uniform in the placement box (shrunk by r_i on non-periodic axes).
  void Draw(int i, double* xi) {
    const double ri = model_.radius[static_cast<std::size_t>(i)];
    for (int a = 0; a < k_; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      if (model_.periodic[ua]) {
        xi[a] = lo_[ua] + (hi_[ua] - lo_[ua]) * rng_.Uniform01();
        if (xi[a] >= hi_[ua]) xi[a] = lo_[ua];
      } else {
        const double a0 = lo_[ua] + ri;
        const double a1 = hi_[ua] - ri;
        if (a1 < a0) {
          throw InputError(fmt::format(
              "particle {} of radius {} does not fit the initial box on axis {}", i, ri, a));
        }
        xi[a] = a0 + (a1 - a0) * rng_.Uniform01();
      }
    }
  }

  // No placed particle in the cells adjacent to xi's overlaps particle i at xi.
  bool ClearOfOthers(int i, const double* xi) const {
    const double ri = model_.radius[static_cast<std::size_t>(i)];
    bool clear = true;
    auto overlaps = [&](int j) {
      double u[3];
      Displacement(model_, xi, &x_[static_cast<std::size_t>(k_ * j)], u);
      double r2 = 0.0;
      for (int a = 0; a < k_; ++a) r2 += u[a] * u[a];
      const double c = ri + model_.radius[static_cast<std::size_t>(j)];
      return r2 < c * c;
    };
    internal::DispatchDimension(k_, [&](auto kk) {
      grid_.ForEachAdjacentCell<kk>(xi, [&](std::int64_t cell) {
        for (int j = head_[static_cast<std::size_t>(cell)]; j >= 0 && clear;
             j = next_[static_cast<std::size_t>(j)]) {
          if (overlaps(j)) clear = false;
        }
      });
    });
    return clear;
  }

  const ParticleModel& model_;
  int k_;
  std::vector<UnitWall> walls_;
  internal::SegmentGrid near_;  // the segments near each candidate
  SplitMix64 rng_;
  Vec3 lo_{}, hi_{};
  internal::CellGrid grid_;
  std::vector<int> head_, next_;  // the placed particles linked per cell
  std::vector<double> x_;
};

}  // namespace

std::vector<double> RandomSequentialAddition(const ParticleModel& model, const Vec3& lo,
                                             const Vec3& hi, std::uint64_t seed,
                                             std::int64_t max_attempts) {
  model.Validate();
  SequentialPlacement placement(model, lo, hi, seed);
  for (int i = 0; i < model.count(); ++i) placement.Place(i, max_attempts);
  return placement.Take();
}

}  // namespace moreau::particles
