// Deposit and Sample: the voxels around an agent and their weights, the same for both.
#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>

#include <fmt/format.h>

#include "fields/team.h"
#include "moreau/common/error.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

constexpr int kMaxStencil = 8;

// The grid and a substrate's periodic axes as the stencils read them, worked out once per call.
struct Lattice {
  int dimension = 0;
  std::int64_t n[3] = {1, 1, 1};       // voxels along each axis
  std::int64_t stride[3] = {1, 1, 1};  // index step along each axis
  bool periodic[3] = {false, false, false};
  double lower[3] = {0.0, 0.0, 0.0};
  double spacing = 1.0;
};

Lattice LatticeOf(const Grid& grid, const Substrate& sub) {
  const std::array<int, 3> n = grid.cells();
  Lattice l;
  l.dimension = grid.dimension;
  l.spacing = grid.spacing;
  for (int a = 0; a < 3; ++a) {
    l.n[a] = n[a];
    if (a > 0) l.stride[a] = l.stride[a - 1] * n[a - 1];
    l.periodic[a] = a < grid.dimension && sub.boundary[2 * a].kind == BoundaryKind::kPeriodic;
    l.lower[a] = grid.lower[a];
  }
  return l;
}

// The voxels an agent reaches and their weights (summing to 1), with each voxel's position along
// every axis.
struct Stencil {
  int size = 0;
  std::int64_t index[kMaxStencil];
  std::int64_t along[kMaxStencil][3];
  double weight[kMaxStencil];
};

// Along one axis of n voxels: the lower voxel, the upper one and the upper's weight.
struct AxisWeights {
  std::int64_t lower = 0;
  std::int64_t upper = 0;
  double fraction = 0.0;
};

// u in voxel units from the lower face. kVoxel: the voxel that holds u; kLinear: the centres on
// either side of u, a position between a face and the first centre all on the face's voxel, or
// wrapped on a periodic axis.
AxisWeights AlongAxis(double u, std::int64_t n, bool periodic, Interpolation interpolation) {
  const auto wrap = [n](double v) {
    v = std::fmod(v, static_cast<double>(n));
    return v < 0.0 ? v + static_cast<double>(n) : v;
  };
  const double top = static_cast<double>(n - 1);
  if (interpolation == Interpolation::kVoxel) {
    const double v = periodic ? wrap(u) : std::clamp(u, 0.0, static_cast<double>(n));
    const auto i = std::min(static_cast<std::int64_t>(v), n - 1);
    return {i, i, 0.0};
  }
  double v = u - 0.5;
  if (periodic) {
    v = wrap(v);
    const auto i = std::min(static_cast<std::int64_t>(v), n - 1);
    return {i, (i + 1) % n, v - static_cast<double>(i)};
  }
  v = std::clamp(v, 0.0, top);
  const auto i = std::min(static_cast<std::int64_t>(v), std::max<std::int64_t>(n - 2, 0));
  return {i, std::min(i + 1, n - 1), v - static_cast<double>(i)};
}

Stencil StencilAt(const Lattice& l, const double* x, Interpolation interpolation) {
  Stencil st;
  st.size = 1;
  st.index[0] = 0;
  st.weight[0] = 1.0;
  for (int a = 0; a < l.dimension; ++a) {
    const AxisWeights w =
        AlongAxis((x[a] - l.lower[a]) / l.spacing, l.n[a], l.periodic[a], interpolation);
    const int size = st.size;
    if (interpolation == Interpolation::kLinear) {
      for (int q = 0; q < size; ++q) {
        st.index[size + q] = st.index[q] + w.upper * l.stride[a];
        st.weight[size + q] = st.weight[q] * w.fraction;
        for (int b = 0; b < a; ++b) st.along[size + q][b] = st.along[q][b];
        st.along[size + q][a] = w.upper;
        st.index[q] += w.lower * l.stride[a];
        st.weight[q] *= 1.0 - w.fraction;
        st.along[q][a] = w.lower;
      }
      st.size = 2 * size;
    } else {
      st.index[0] += w.lower * l.stride[a];
      st.along[0][a] = w.lower;
    }
  }
  return st;
}

// The central difference along `axis` at voxel v, the i-th along that axis (one-sided at a face
// that is not periodic).
double Derivative(const Lattice& l, std::span<const double> c, std::int64_t v, std::int64_t i,
                  int axis) {
  const std::int64_t na = l.n[axis];
  const std::int64_t stride = l.stride[axis];
  if (na == 1) return 0.0;
  if (l.periodic[axis]) {
    const std::int64_t up = v + ((i + 1) % na - i) * stride;
    const std::int64_t down = v + ((i + na - 1) % na - i) * stride;
    return (c[up] - c[down]) / (2.0 * l.spacing);
  }
  const std::int64_t up = i + 1 < na ? v + stride : v;
  const std::int64_t down = i > 0 ? v - stride : v;
  return (c[up] - c[down]) / (static_cast<double>(up - down) / stride * l.spacing);
}

// Throws InputError(key) unless `values` is empty or holds `count` finite entries ≥ `minimum`.
void CheckAgentValues(const char* key, std::span<const double> values, std::size_t count,
                      double minimum, bool strict) {
  if (values.empty()) return;
  if (values.size() != count) {
    throw InputError(key, fmt::format("has {} entries for {} agents", values.size(), count));
  }
  for (std::size_t i = 0; i < count; ++i) {
    const double v = values[i];
    if (!std::isfinite(v) || v < minimum || (strict && v == minimum)) {
      throw InputError(key, fmt::format("agent {}: must be finite and {} {} (got {})", i,
                                        strict ? ">" : "≥", minimum, v));
    }
  }
}

std::size_t AgentCount(const Grid& grid, std::span<const double> positions) {
  const auto k = static_cast<std::size_t>(grid.dimension);
  if (positions.size() % k != 0) {
    throw InputError("positions", fmt::format("has {} entries, not a multiple of the dimension {}",
                                              positions.size(), k));
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!std::isfinite(positions[i])) {
      throw InputError("positions", fmt::format("agent {}: must be finite", i / k));
    }
  }
  return positions.size() / k;
}

}  // namespace

void FieldSet::Deposit(int s, std::span<const double> positions, std::span<const double> volumes,
                       std::span<const double> secretion, std::span<const double> saturation,
                       std::span<const double> uptake, std::span<const double> amount_rate,
                       Interpolation interpolation) {
  const auto u = static_cast<std::size_t>(s);
  const Substrate& sub = substrates_.at(u);
  const std::size_t count = AgentCount(grid_, positions);
  const double inf = -std::numeric_limits<double>::infinity();
  CheckAgentValues("volumes", volumes, count, 0.0, true);
  CheckAgentValues("secretion", secretion, count, 0.0, false);
  CheckAgentValues("saturation", saturation, count, inf, false);
  CheckAgentValues("uptake", uptake, count, 0.0, false);
  CheckAgentValues("amount_rate", amount_rate, count, inf, false);
  if (volumes.empty() && (!secretion.empty() || !uptake.empty())) {
    throw InputError("volumes", "needed with secretion or uptake (rates per agent volume)");
  }
  sources_written_[u] = 1;
  const Lattice lattice = LatticeOf(grid_, sub);
  const auto k = static_cast<std::size_t>(grid_.dimension);
  const std::size_t reach = interpolation == Interpolation::kLinear ? std::size_t{1} << k : 1;
  const double inverse_volume = 1.0 / grid_.voxel_volume();
  const int threads = internal::TeamSize(threads_, static_cast<std::int64_t>(count));
  // The stencils first, each agent's own (any split over threads), then each thread adds to its
  // own range of voxels, the agents in order: every voxel receives its terms in agent order, the
  // same bits for any thread count.
  deposit_voxel_.resize(count * reach);
  deposit_share_.resize(count * reach);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (std::size_t i = 0; i < count; ++i) {
    const Stencil st = StencilAt(lattice, positions.data() + k * i, interpolation);
    for (std::size_t q = 0; q < reach; ++q) {
      deposit_voxel_[reach * i + q] = st.index[q];
      deposit_share_[reach * i + q] = st.weight[q] * inverse_volume;
    }
  }
  const bool with_target = !secretion.empty() && !saturation.empty();
  const std::int64_t voxels = grid_.voxel_count();
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    const std::int64_t team = omp_get_num_threads();
    const std::int64_t t = omp_get_thread_num();
    const std::int64_t lo = voxels * t / team;
    const std::int64_t hi = voxels * (t + 1) / team;
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t q = reach * i; q < reach * (i + 1); ++q) {
        const std::int64_t voxel = deposit_voxel_[q];
        if (voxel < lo || voxel >= hi) continue;
        const auto v = static_cast<std::size_t>(voxel);
        const double share = deposit_share_[q];
        if (!volumes.empty()) {
          const double filled = share * volumes[i];
          if (!secretion.empty()) secretion_[u][v] += secretion[i] * filled;
          if (with_target) secretion_target_[u][v] += secretion[i] * saturation[i] * filled;
          if (!uptake.empty()) uptake_[u][v] += uptake[i] * filled;
        }
        if (!amount_rate.empty()) source_[u][v] += amount_rate[i] * share;
      }
    }
  }
}

void FieldSet::Sample(int s, std::span<const double> positions, Interpolation interpolation,
                      std::span<double> value, std::span<double> gradient) const {
  const Substrate& sub = substrates_.at(static_cast<std::size_t>(s));
  const std::size_t count = AgentCount(grid_, positions);
  const auto k = static_cast<std::size_t>(grid_.dimension);
  if (value.size() != count) {
    throw InputError("value", fmt::format("has {} entries for {} agents", value.size(), count));
  }
  if (!gradient.empty() && gradient.size() != k * count) {
    throw InputError("gradient", fmt::format("has {} entries for {} agents in {} dimensions",
                                             gradient.size(), count, k));
  }
  const std::span<const double> c = values(s);
  // Each agent's value and gradient are its own: any split over threads gives the same bits
  // (a large population is split like a large grid).
  const int threads = internal::TeamSize(threads_, static_cast<std::int64_t>(count));
  const Lattice lattice = LatticeOf(grid_, sub);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (std::size_t i = 0; i < count; ++i) {
    const Stencil st = StencilAt(lattice, positions.data() + k * i, interpolation);
    double sum = 0.0;
    for (int q = 0; q < st.size; ++q)
      sum += st.weight[q] * c[static_cast<std::size_t>(st.index[q])];
    value[i] = sum;
    if (gradient.empty()) continue;
    for (std::size_t a = 0; a < k; ++a) {
      double g = 0.0;
      for (int q = 0; q < st.size; ++q) {
        g +=
            st.weight[q] * Derivative(lattice, c, st.index[q], st.along[q][a], static_cast<int>(a));
      }
      gradient[k * i + a] = g;
    }
  }
}

}  // namespace moreau::fields
