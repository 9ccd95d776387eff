#include "moreau/particles/model.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "particles/cell_list.h"
#include "particles/neighbour_list.h"

namespace moreau::particles {

double ParticleModel::max_radius() const {
  return radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
}

void ParticleModel::AddBoxWalls(const Vec3& lo, const Vec3& hi) {
  for (int a = 0; a < dimension; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (periodic[ua]) continue;
    Wall low;
    low.normal = {0.0, 0.0, 0.0};
    low.normal[ua] = 1.0;
    low.offset = lo[ua];
    walls.push_back(low);
    Wall high;
    high.normal = {0.0, 0.0, 0.0};
    high.normal[ua] = -1.0;
    high.offset = -hi[ua];
    walls.push_back(high);
  }
}

void ParticleModel::Validate() const {
  if (dimension < 1 || dimension > 3) {
    throw InputError(fmt::format("dimension must be 1, 2 or 3 (got {})", dimension));
  }
  if (radius.empty()) throw InputError("a particle model needs at least one particle");
  for (std::size_t i = 0; i < radius.size(); ++i) {
    if (!(radius[i] > 0.0) || !std::isfinite(radius[i])) {
      throw InputError(fmt::format("radius of particle {} must be > 0 (got {})", i, radius[i]));
    }
  }
  if (!mobility.empty() && mobility.size() != radius.size()) {
    throw InputError(
        fmt::format("mobility has {} entries for {} particles", mobility.size(), radius.size()));
  }
  if (!stable_ids.empty() && stable_ids.size() != radius.size()) {
    throw InputError(fmt::format("stable_ids has {} entries for {} particles", stable_ids.size(),
                                 radius.size()));
  }
  for (std::size_t i = 0; i < stable_ids.size(); ++i) {
    if (stable_ids[i] < 0 || stable_ids[i] >= (std::int64_t{1} << 62)) {
      throw InputError(
          fmt::format("stable id of particle {} must be in [0, 2^62) (got {})", i, stable_ids[i]));
    }
  }
  for (std::size_t i = 0; i < mobility.size(); ++i) {
    if (!(mobility[i] > 0.0) || !std::isfinite(mobility[i])) {
      throw InputError(fmt::format("mobility of particle {} must be > 0 (got {})", i, mobility[i]));
    }
  }
  const auto k = static_cast<std::size_t>(dimension);
  for (std::size_t w = 0; w < walls.size(); ++w) {
    double n2 = 0.0;
    bool finite = std::isfinite(walls[w].offset);
    for (std::size_t a = 0; a < k; ++a) {
      n2 += walls[w].normal[a] * walls[w].normal[a];
      finite = finite && std::isfinite(walls[w].normal[a]);
    }
    if (!finite) throw InputError(fmt::format("walls[{}] must be finite", w));
    if (!(n2 > 0.0)) throw InputError(fmt::format("walls[{}].normal must be non-zero", w));
  }
  for (std::size_t s = 0; s < spheres.size(); ++s) {
    if (!(spheres[s].radius > 0.0) || !std::isfinite(spheres[s].radius)) {
      throw InputError(
          fmt::format("spheres[{}].radius must be > 0 (got {})", s, spheres[s].radius));
    }
    for (std::size_t a = 0; a < k; ++a) {
      if (!std::isfinite(spheres[s].center[a])) {
        throw InputError(fmt::format("spheres[{}].center must be finite", s));
      }
    }
  }
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (dimension != 2) {
      throw InputError(
          fmt::format("segments need dimension 2 (segments[{}] given in {}D)", s, dimension));
    }
    const auto& g = segments[s];
    if (!std::isfinite(g.a[0]) || !std::isfinite(g.a[1]) || !std::isfinite(g.b[0]) ||
        !std::isfinite(g.b[1])) {
      throw InputError(fmt::format("segments[{}] must be finite", s));
    }
    if (g.a[0] == g.b[0] && g.a[1] == g.b[1]) {
      throw InputError(fmt::format("segments[{}] needs a ≠ b", s));
    }
  }
  const double rmax = max_radius();
  for (std::size_t a = 0; a < k; ++a) {
    if (!periodic[a]) continue;
    const double lo = domain_lo[a];
    const double hi = domain_hi[a];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) {
      throw InputError(
          fmt::format("domain of periodic axis {} needs lo < hi (got [{}, {}))", a, lo, hi));
    }
    if (!(4.0 * rmax < hi - lo)) {
      const auto it = std::max_element(radius.begin(), radius.end());
      throw InputError(fmt::format(
          "radius of particle {} ({}) is too large for periodic axis {} of length {}: need 4 r < L",
          it - radius.begin(), rmax, a, hi - lo));
    }
  }
}

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

// How deep particle i at x is inside a wall or obstacle (> tol·r_i), as a message; empty if not.
std::string FixedSetViolation(const ParticleModel& model, const std::vector<UnitWall>& walls, int i,
                              const double* x, double tol) {
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
  for (std::size_t s = 0; s < model.segments.size(); ++s) {
    const double g =
        internal::SegmentGap(x, model.segments[s].a.data(), model.segments[s].b.data(), r);
    if (g < -tol * r) return fmt::format("particle {} is inside segments[{}] by {}", i, s, -g);
  }
  return {};
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
  for (int i = 0; i < n; ++i) {
    const std::string v =
        FixedSetViolation(model, walls, i, &positions[static_cast<std::size_t>(k * i)], tol);
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

std::vector<double> RandomSequentialAddition(const ParticleModel& model, const Vec3& lo,
                                             const Vec3& hi, std::uint64_t seed,
                                             std::int64_t max_attempts) {
  model.Validate();
  const int k = model.dimension;
  const int n = model.count();
  Vec3 glo = lo, ghi = hi;
  for (int a = 0; a < k; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (model.periodic[ua]) {
      glo[ua] = model.domain_lo[ua];
      ghi[ua] = model.domain_hi[ua];
    } else if (!(lo[ua] <= hi[ua]) || !std::isfinite(lo[ua]) || !std::isfinite(hi[ua])) {
      throw InputError(
          fmt::format("initial box on axis {} needs lo ≤ hi (got [{}, {}])", a, lo[ua], hi[ua]));
    }
  }
  const std::vector<UnitWall> walls = UnitWalls(model);
  // Placed particles linked per cell of the particle core's grid (edge ≥ 2 max r).
  const internal::PeriodicBox box = internal::PeriodicBox::Of(model);
  internal::CellGrid grid;
  grid.Fit(k, glo.data(), ghi.data(), box, 2.0 * model.max_radius(),
           4 * static_cast<std::int64_t>(n));
  std::vector<int> head(static_cast<std::size_t>(grid.cells()), -1);
  std::vector<int> next(static_cast<std::size_t>(n), -1);
  std::vector<double> x(static_cast<std::size_t>(k) * static_cast<std::size_t>(n), 0.0);
  SplitMix64 rng(seed);
  auto uniform = [&rng] { return rng.Uniform01(); };
  for (int i = 0; i < n; ++i) {
    const double ri = model.radius[static_cast<std::size_t>(i)];
    double* xi = &x[static_cast<std::size_t>(k * i)];
    bool placed = false;
    for (std::int64_t attempt = 0; attempt < max_attempts && !placed; ++attempt) {
      for (int a = 0; a < k; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        if (model.periodic[ua]) {
          xi[a] = glo[ua] + (ghi[ua] - glo[ua]) * uniform();
          if (xi[a] >= ghi[ua]) xi[a] = glo[ua];
        } else {
          const double a0 = glo[ua] + ri;
          const double a1 = ghi[ua] - ri;
          if (a1 < a0) {
            throw InputError(
                fmt::format("particle {} of radius {} does not fit the initial box "
                            "on axis {}",
                            i, ri, a));
          }
          xi[a] = a0 + (a1 - a0) * uniform();
        }
      }
      if (!FixedSetViolation(model, walls, i, xi, 0.0).empty()) continue;
      placed = true;
      auto overlaps = [&](int j) {
        double u[3];
        Displacement(model, xi, &x[static_cast<std::size_t>(k * j)], u);
        double r2 = 0.0;
        for (int a = 0; a < k; ++a) r2 += u[a] * u[a];
        const double c = ri + model.radius[static_cast<std::size_t>(j)];
        return r2 < c * c;
      };
      internal::DispatchDimension(k, [&](auto kk) {
        grid.ForEachAdjacentCell<kk>(xi, [&](std::int64_t cell) {
          for (int j = head[static_cast<std::size_t>(cell)]; j >= 0 && placed;
               j = next[static_cast<std::size_t>(j)]) {
            if (overlaps(j)) placed = false;
          }
        });
      });
    }
    if (!placed) {
      throw InputError(fmt::format(
          "could not place particle {} without overlap in {} attempts (placed {} of {})", i,
          max_attempts, i, n));
    }
    const std::int64_t cell = grid.CellOf(xi);
    next[static_cast<std::size_t>(i)] = head[static_cast<std::size_t>(cell)];
    head[static_cast<std::size_t>(cell)] = i;
  }
  return x;
}

}  // namespace moreau::particles
