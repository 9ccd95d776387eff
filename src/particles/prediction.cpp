#include "particles/prediction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "particles/noise.h"
#include "particles/step_context.h"

namespace moreau::particles::internal {

DriftParameters::DriftParameters(const Forces& forces, int k, double h) {
  trap = forces.trap.has_value();
  gamma = trap ? forces.trap->gamma : 0.0;
  for (int a = 0; a < k; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (trap) center[a] = forces.trap->center[ua];
    f0[a] = forces.constant_force[ua];
    any_constant = any_constant || f0[a] != 0.0;
  }
  propulsion = forces.propulsion.has_value() && forces.propulsion->speed > 0.0;
  v0 = propulsion ? forces.propulsion->speed : 0.0;
  segment = propulsion && forces.propulsion->target_end.has_value();
  exit = propulsion && forces.propulsion->exit_direction.has_value();
  double n2 = 0.0;
  for (int a = 0; a < k; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (propulsion) target[a] = forces.propulsion->target[ua];
    if (segment) target_end[a] = (*forces.propulsion->target_end)[ua];
    if (exit) exit_direction[a] = (*forces.propulsion->exit_direction)[ua];
    n2 += exit_direction[a] * exit_direction[a];
  }
  if (exit) {
    for (int a = 0; a < k; ++a) exit_direction[a] /= std::sqrt(n2);
  }
  if (propulsion) route_owner = forces.propulsion->route;
  route = route_owner.get();
  if (route != nullptr && k != 2) {
    throw InputError(fmt::format("forces.propulsion.route needs dimension 2 (got {})", k));
  }
  fixed = propulsion && forces.propulsion->direction.has_value();
  if (fixed) {
    double d2 = 0.0;
    for (int a = 0; a < k; ++a) {
      direction[a] = (*forces.propulsion->direction)[static_cast<std::size_t>(a)];
      d2 += direction[a] * direction[a];
    }
    for (int a = 0; a < k; ++a) direction[a] /= std::sqrt(d2);
  }
  if (propulsion) {
    speed_sd = forces.walking.speed_sd;
    density = forces.walking.density.has_value();
    if (density) density_law = *forces.walking.density;
    collision_free = forces.walking.collision_free.has_value();
    if (collision_free) walk = *forces.walking.collision_free;
  }
  if (forces.attraction && forces.attraction->attracts()) {
    attraction_stiffness = forces.attraction->stiffness;
    attraction_range = forces.attraction->range;
    class_stiffness = forces.attraction->class_stiffness;
    classes = forces.attraction->classes();
  }
  sigma = forces.diffusion > 0.0 ? std::sqrt(2.0 * forces.diffusion * h) : 0.0;
}

Prediction::Prediction(const Forces& forces, const PeriodicBox& box, int n, double h,
                       std::uint64_t seed, bool uniform_mobility)
    : parameters_(forces, box.k, h),
      box_(box),
      n_(n),
      h_(h),
      seed_(seed),
      uniform_mobility_(uniform_mobility) {
  if (attracts()) force_.assign(static_cast<std::size_t>(box.k) * static_cast<std::size_t>(n), 0.0);
  if (measures_density()) {
    if (box.k != 2) {
      throw InputError(
          fmt::format("forces.walking.density: a density in persons per area needs dimension 2 "
                      "(got {})",
                      box.k));
    }
    neighbours_.assign(static_cast<std::size_t>(n), 0);
    speed_factor_.assign(static_cast<std::size_t>(n), 1.0);
  }
  if (walks_collision_free()) {
    if (box.k != 2) {
      throw InputError(fmt::format(
          "forces.walking.collision_free: the collision-free speed model needs dimension 2 (got {})",
          box.k));
    }
    walk_.assign(2 * static_cast<std::size_t>(n), 0.0);
    headway_.assign(static_cast<std::size_t>(n), 0.0);
  }
}

void GatherRows(const std::vector<int>& perm, int width, int threads, std::vector<double>* v,
                std::vector<double>* scratch) {
  if (v->empty()) return;
  scratch->resize(v->size());
  const int n = static_cast<int>(perm.size());
  const double* src = v->data();
  double* dst = scratch->data();
  auto gather = [&](auto w) {  // the row width as a constant: the copy unrolled
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int s = 0; s < n; ++s) {
      const int o = perm[static_cast<std::size_t>(s)];
      for (int a = 0; a < w; ++a) dst[w * s + a] = src[w * o + a];
    }
  };
  if (width == 1) {
    gather(std::integral_constant<int, 1>());
  } else if (width == 2) {
    gather(std::integral_constant<int, 2>());
  } else {
    gather(std::integral_constant<int, 3>());
  }
  v->swap(*scratch);
}

void Prediction::Reorder(const std::vector<int>& perm, int threads) {
  GatherRows(perm, box_.k, threads, &force_, &scratch_);
  GatherRows(perm, 1, threads, &speed_factor_, &scratch_);
}

template <int K, bool P, bool Matrix>
void Prediction::AttractionImpl(const double* x, const double* radius, const int* id,
                                const int* cls, double uniform, const NeighbourList& list,
                                const Colouring& colouring, const CellList& cells,
                                bool lexicographic, int threads) {
  const double* matrix = parameters_.class_stiffness.data();
  const int classes = parameters_.classes;
  const double range = parameters_.attraction_range;
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  double* f = force_.data();
  std::fill(force_.begin(), force_.end(), 0.0);
  auto rows = [&](int begin, int end) {
    for (int s = begin; s < end; ++s) {
      const double rs = radius[s];
      for (std::int64_t p = row_start[s]; p < row_start[s + 1]; ++p) {
        const int t = nbr[p];
        double u[K];
        list.Displacement<K, P>(x, s, t, p, u);
        const double r = std::sqrt(SquaredNorm<K>(u));
        const double g = r - (rs + radius[t]);
        if (!(g > 0.0 && g < range)) continue;
        double stiffness = uniform;
        if constexpr (Matrix) stiffness = matrix[classes * cls[id[s]] + cls[id[t]]];
        const double scale = stiffness * g * (1.0 - g / range) / r;
        for (int a = 0; a < K; ++a) {
          f[K * s + a] -= scale * u[a];
          f[K * t + a] += scale * u[a];
        }
      }
    }
  };
  if (lexicographic) {
    rows(0, n_);
    return;
  }
#pragma omp parallel num_threads(threads)
  ForEachBlockByColour(colouring, cells, rows);
}

void Prediction::Attraction(const StepContext& context) {
  const ParticleStore& store = *context.store;
  const std::vector<int>& cls = context.model.adhesion_class;
  const bool matrix = parameters_.classes > 0 && !cls.empty();
  // A matrix without classes: every particle is of class 0.
  const double uniform = parameters_.classes > 0 && cls.empty()
                             ? parameters_.class_stiffness.front()
                             : parameters_.attraction_stiffness;
  DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
    const auto run = [&](auto m) {
      AttractionImpl<k, p, m>(store.current.data(), store.radius.data(), store.id.data(),
                              cls.data(), uniform, context.list, context.colouring, context.cells,
                              context.lexicographic, context.threads);
    };
    if (matrix) {
      run(std::true_type());
    } else {
      run(std::false_type());
    }
  });
}

template <int K, bool P>
void Prediction::LocalDensityImpl(const double* x, const NeighbourList& list,
                                  const Colouring& colouring, const CellList& cells,
                                  bool lexicographic, int threads) {
  const double radius2 = parameters_.density_law.radius * parameters_.density_law.radius;
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  int* count = neighbours_.data();
  std::fill(neighbours_.begin(), neighbours_.end(), 0);
  auto rows = [&](int begin, int end) {
    for (int s = begin; s < end; ++s) {
      for (std::int64_t p = row_start[s]; p < row_start[s + 1]; ++p) {
        const int t = nbr[p];
        double u[K];
        list.Displacement<K, P>(x, s, t, p, u);
        if (SquaredNorm<K>(u) < radius2) {
          ++count[s];
          ++count[t];
        }
      }
    }
  };
  if (lexicographic) {
    rows(0, n_);
  } else {
#pragma omp parallel num_threads(threads)
    ForEachBlockByColour(colouring, cells, rows);
  }
  const double area = std::numbers::pi * radius2;
  for (int s = 0; s < n_; ++s) {
    const auto us = static_cast<std::size_t>(s);
    speed_factor_[us] =
        WeidmannSpeedFactor(parameters_.density_law, (1.0 + neighbours_[us]) / area);
  }
}

void Prediction::LocalDensity(const StepContext& context) {
  DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
    LocalDensityImpl<k, p>(context.store->current.data(), context.list, context.colouring,
                           context.cells, context.lexicographic, context.threads);
  });
}

namespace {

// The self-propulsion velocity v0 e0 of a particle at xw (wrapped), added to v; nothing when
// the particle is at its target.
template <int K>
[[gnu::always_inline]] inline void AddPropulsion(const DriftParameters& d, const double* xw,
                                                 double speed, double* v) {
  double e[K];
  DesiredDirection<K>(d, xw, e);
  if (SquaredNorm<K>(e) == 0.0) return;
  for (int a = 0; a < K; ++a) v[a] += speed * e[a];
}

}  // namespace

// The rows of one noise batch of PredictImpl: the noise of a batch is drawn first, in one
// vectorised loop (noise.h), then this drift loop adds it; the batch's totals are plain local
// scalars until its end. The loop reads PredictImpl's local scalars through these references
// (as a lambda capturing them would).
template <int K, bool P, bool Noise>
struct PredictRows {
  const double* const& x;
  const bool (&wrap_axis)[3];
  const double (&lo)[3];
  const double (&len)[3];
  const bool& trap;
  const double& gamma;
  const double (&center)[3];
  const bool& any_constant;
  const double (&f0)[3];
  const bool& attract;
  const double* const& fa;
  const bool& uniform_mobility;
  const double* const& mobility;
  const bool& propulsion;
  const DriftParameters& d;
  const bool& crowd_speeds;
  const std::uint64_t& seed;
  const std::int64_t* const& key;
  const int* const& id;
  const double* const& factor;
  const double* const& walk;
  const double* const& active;
  const double& h;
  const double& sigma;
  double* const& y;
  const double* const& ref;
  const double& quarter2;

  void operator()(int begin, int end, [[maybe_unused]] const double* xi,
                  PredictionTotals* t) const {
    double worst = 0.0, extent = 0.0, worst2 = 0.0;
    std::int64_t bad = std::numeric_limits<std::int64_t>::max(), far_count = 0;
    for (int s = begin; s < end; ++s) {
      double xw[K];
      for (int a = 0; a < K; ++a) {
        xw[a] = x[K * s + a];
        if constexpr (P) {
          if (wrap_axis[a]) xw[a] = Wrap(xw[a], lo[a], len[a]);
        }
      }
      double F[K];
      for (int a = 0; a < K; ++a) F[a] = trap ? -gamma * (xw[a] - center[a]) : 0.0;
      if (any_constant) {
        for (int a = 0; a < K; ++a) F[a] += f0[a];
      }
      if (attract) {
        for (int a = 0; a < K; ++a) F[a] += fa[K * s + a];
      }
      const double mu = uniform_mobility ? 1.0 : mobility[s];
      double v[K];
      for (int a = 0; a < K; ++a) v[a] = mu * F[a];
      if (walk != nullptr) {
        for (int a = 0; a < K; ++a) v[a] += walk[K * s + a];
      } else if (propulsion) {
        double speed = d.v0;
        if (crowd_speeds) {
          speed = DesiredSpeed(seed, key != nullptr ? key[s] : id[s], d.v0, d.speed_sd);
          if (factor != nullptr) speed *= factor[s];
        }
        AddPropulsion<K>(d, xw, speed, v);
      }
      if (active != nullptr) {
        for (int a = 0; a < K; ++a) v[a] += active[K * s + a];
      }
      double yy[K];
      for (int a = 0; a < K; ++a) yy[a] = x[K * s + a] + h * v[a];
      if constexpr (Noise) {
        for (int a = 0; a < K; ++a) yy[a] += sigma * xi[a * kNoiseBatch + (s - begin)];
      }
      double d2 = 0.0, far = 0.0;
      bool finite = true;
      for (int a = 0; a < K; ++a) {
        y[K * s + a] = yy[a];
        finite = finite && std::isfinite(yy[a]);
        const double dd = yy[a] - x[K * s + a];
        d2 += dd * dd;
        far = std::max(far, std::abs(yy[a]));
      }
      if (!finite) {
        bad = std::min<std::int64_t>(bad, id[s]);
      } else {
        worst = std::max(worst, d2);
        extent = std::max(extent, far);
      }
      if (ref != nullptr) {
        double e2 = 0.0;
        for (int a = 0; a < K; ++a) {
          const double de = yy[a] - ref[K * s + a];
          e2 += de * de;
        }
        worst2 = std::max(worst2, e2);
        far_count += e2 > quarter2 ? 1 : 0;
      }
    }
    *t = {worst, extent, worst2, bad, far_count};
  }
};

template <int K, bool P, bool Noise>
void Prediction::PredictImpl(const double* x, double* y, const int* id, const std::int64_t* key,
                             const double* active, const double* mobility, std::int64_t step,
                             int threads, double* max_move, std::int64_t* bad_id,
                             double* max_coordinate, ExactBound* bound) const {
  // Plain local scalars, not members or a struct: they stay in registers or the loop's operands
  // (a member or a struct copy could alias y or crowd out the running maximum).
  const DriftParameters& d = parameters_;
  const bool trap = d.trap, any_constant = d.any_constant, propulsion = d.propulsion;
  const double gamma = d.gamma, sigma = d.sigma, h = h_;
  double center[3], f0[3];
  for (int a = 0; a < 3; ++a) {
    center[a] = d.center[a];
    f0[a] = d.f0[a];
  }
  bool wrap_axis[3] = {false, false, false};
  double lo[3] = {0, 0, 0}, len[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    wrap_axis[a] = box_.periodic[a] && (trap || propulsion);
    lo[a] = box_.lo[a];
    len[a] = box_.len[a];
  }
  const std::uint64_t seed = seed_;
  const bool uniform_mobility = uniform_mobility_;
  const int n = n_;
  const double* fa = force_.data();
  const bool attract = !force_.empty();
  const double* factor = speed_factor_.empty() ? nullptr : speed_factor_.data();
  const bool crowd_speeds = d.speed_sd > 0.0 || factor != nullptr;
  const double* walk = walk_.empty() ? nullptr : walk_.data();
  const double* ref = bound != nullptr ? bound->reference : nullptr;
  const double quarter2 = bound != nullptr ? bound->quarter2 : 0.0;
  const PredictRows<K, P, Noise> rows{x,        wrap_axis,  lo,     len,
                                      trap,     gamma,      center, any_constant,
                                      f0,       attract,    fa,     uniform_mobility,
                                      mobility, propulsion, d,      crowd_speeds,
                                      seed,     key,        id,     factor,
                                      walk,     active,     h,      sigma,
                                      y,        ref,        quarter2};
  ReportPrediction(OverNoiseBatches<K, Noise>(n, threads, seed, key, id, step, rows), max_move,
                   bad_id, max_coordinate, bound);
}

void ReportPrediction(const PredictionTotals& totals, double* max_move, std::int64_t* bad_id,
                      double* max_coordinate, ExactBound* bound) {
  *max_move = std::sqrt(totals.worst);
  if (max_coordinate != nullptr) *max_coordinate = totals.extent;
  *bad_id = totals.bad == std::numeric_limits<std::int64_t>::max() ? -1 : totals.bad;
  if (bound != nullptr) {
    bound->worst2 = totals.worst2;
    bound->far = totals.far;
  }
}

PredictionOutcome Prediction::Predict(StepContext& context, std::int64_t step,
                                      ExactBound* bound) const {
  ParticleStore& store = *context.store;
  const double* x = store.current.data();
  double* y = store.predicted.data();
  const int* id = store.id.data();
  const std::int64_t* key = store.noise_key.empty() ? nullptr : store.noise_key.data();
  const double* active = store.active.empty() ? nullptr : store.active.data();
  const double* mobility = store.mobility.data();
  const int threads = context.threads;
  PredictionOutcome out;
  // Without noise the loop makes no call, so its running maximum stays in a register; with noise
  // the batch's draw comes before its drift loop.
  const bool noise = parameters_.sigma > 0.0;
  if (Plain()) {
    PredictPlainDispatch(x, y, id, key, active, step, threads, &out.max_move, &out.bad_id,
                         &out.max_coordinate, bound);
    return out;
  }
  DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
    if (noise) {
      PredictImpl<k, p, true>(x, y, id, key, active, mobility, step, threads, &out.max_move,
                              &out.bad_id, &out.max_coordinate, bound);
    } else {
      PredictImpl<k, p, false>(x, y, id, key, active, mobility, step, threads, &out.max_move,
                               &out.bad_id, &out.max_coordinate, bound);
    }
  });
  return out;
}

}  // namespace moreau::particles::internal
