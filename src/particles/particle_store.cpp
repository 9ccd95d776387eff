#include "particles/particle_store.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "moreau/common/error.h"
#include "particles/prediction.h"

namespace moreau::particles::internal {

ParticleStore::ParticleStore(const ParticleModel& model, std::span<const double> positions,
                             std::span<const double> active_velocity)
    : k(model.dimension), n(model.count()) {
  noise_key = model.stable_ids;
  active.assign(active_velocity.begin(), active_velocity.end());
  current.assign(positions.begin(), positions.end());
  predicted.assign(current.size(), 0.0);
  radius = model.radius;
  mobility.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) mobility[static_cast<std::size_t>(i)] = model.mobility_of(i);
  id.resize(static_cast<std::size_t>(n));
  std::iota(id.begin(), id.end(), 0);
  uniform_radius_ =
      std::all_of(radius.begin(), radius.end(), [&](double r) { return r == radius.front(); });
  uniform_mobility_ = std::all_of(mobility.begin(), mobility.end(),
                                  [&](double m) { return m == mobility.front(); });
}

// Radius and mobility are gathered only when they differ between particles (a uniform array is
// the same in any order).
void ParticleStore::Reorder(const std::vector<int>& perm, int threads, bool with_current,
                            const std::vector<double>* copied, double* copy) {
  MOREAU_ASSERT(copied == nullptr || copied == &predicted || (copied == &current && with_current));
  const bool copy_predicted = copied == &predicted;
  const bool copy_current = copied == &current;
  if (!uniform_radius_) GatherRows(perm, 1, threads, &radius, &scratch1_);
  if (!uniform_mobility_) GatherRows(perm, 1, threads, &mobility, &scratch1_);
  GatherRows(perm, k, threads, &active, &scratch_k_);
  // The positions, ids and keys every engine has, in one pass.
  scratch_k_.resize(predicted.size());
  if (with_current) scratch_current_.resize(current.size());
  scratch_id_.resize(id.size());
  const bool keyed = !noise_key.empty();
  if (keyed) scratch_key_.resize(noise_key.size());
  auto gather = [&](auto kk) {
    constexpr int K = kk;
    const double* cur = current.data();
    const double* pred = predicted.data();
    double* cur2 = scratch_current_.data();
    double* pred2 = scratch_k_.data();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int s = 0; s < n; ++s) {
      const int o = perm[static_cast<std::size_t>(s)];
      if (s + 24 < n) __builtin_prefetch(pred + K * perm[static_cast<std::size_t>(s) + 24]);
      double row[K];  // loaded once: the stores below might alias pred for the compiler
      for (int a = 0; a < K; ++a) row[a] = pred[K * o + a];
      for (int a = 0; a < K; ++a) pred2[K * s + a] = row[a];
      if (copy_predicted) {
        for (int a = 0; a < K; ++a) copy[K * s + a] = row[a];
      }
      if (with_current) {
        for (int a = 0; a < K; ++a) row[a] = cur[K * o + a];
        for (int a = 0; a < K; ++a) cur2[K * s + a] = row[a];
        if (copy_current) {  // copy_current implies with_current (asserted above)
          for (int a = 0; a < K; ++a) copy[K * s + a] = row[a];
        }
      }
      scratch_id_[static_cast<std::size_t>(s)] = id[static_cast<std::size_t>(o)];
      if (keyed) {
        scratch_key_[static_cast<std::size_t>(s)] = noise_key[static_cast<std::size_t>(o)];
      }
    }
  };
  if (k == 1) {
    gather(std::integral_constant<int, 1>());
  } else if (k == 2) {
    gather(std::integral_constant<int, 2>());
  } else {
    gather(std::integral_constant<int, 3>());
  }
  predicted.swap(scratch_k_);
  if (with_current) current.swap(scratch_current_);
  id.swap(scratch_id_);
  if (keyed) noise_key.swap(scratch_key_);
}

void ParticleStore::GatherCurrent(const std::vector<int>& perm, int threads) {
  GatherRows(perm, k, threads, &current, &scratch_current_);
}

std::vector<int> ParticleStore::SlotsOf() const {
  std::vector<int> slot_of(id.size());
  for (int s = 0; s < n; ++s) {
    slot_of[static_cast<std::size_t>(id[static_cast<std::size_t>(s)])] = s;
  }
  return slot_of;
}

void ParticleStore::CopyPositionsById(const PeriodicBox& box, std::span<double> out,
                                      int threads) const {
  MOREAU_ASSERT(out.size() == current.size());
  // A small population's copy (a Python drift reads it every step) is cheaper than a parallel
  // region's start.
#pragma omp parallel for num_threads(threads) schedule(static) if (n >= 4096)
  for (int s = 0; s < n; ++s) {
    const int i = id[static_cast<std::size_t>(s)];
    for (int a = 0; a < k; ++a) {
      double v = current[static_cast<std::size_t>(k * s + a)];
      if (box.periodic[a]) v = Wrap(v, box.lo[a], box.len[a]);
      out[static_cast<std::size_t>(k * i + a)] = v;
    }
  }
}

namespace {

// Two doubles in one register (GCC and Clang vector extension): a 2-D agent's velocity is one
// load, one store and one zeroing store.
using Pair = double __attribute__((vector_size(16)));

// The gather of TakeActive for K = k components. Returns whether the sum of the values is
// finite: true proves every value finite (one addition per value, no branch); false, which a
// sum of huge finite values can also give, sends TakeActive to its exact check.
template <int K, bool kAdded>
bool GatherActive(const int* id, int n, double* velocity, const double* added, double* active) {
  if constexpr (K == 2) {
    Pair check = {0.0, 0.0};
    const Pair zero = {0.0, 0.0};
    for (int s = 0; s < n; ++s) {
      const std::size_t from = 2 * static_cast<std::size_t>(id[s]);
      Pair x;
      std::memcpy(&x, velocity + from, sizeof x);
      std::memcpy(velocity + from, &zero, sizeof x);
      if constexpr (kAdded) {
        Pair y;
        std::memcpy(&y, added + from, sizeof y);
        x += y;
      }
      check += x;
      std::memcpy(active + 2 * static_cast<std::size_t>(s), &x, sizeof x);
    }
    return std::isfinite(check[0] + check[1]);
  } else {
    double check = 0.0;
    for (int s = 0; s < n; ++s) {
      const std::size_t from = static_cast<std::size_t>(K) * static_cast<std::size_t>(id[s]);
      for (int a = 0; a < K; ++a) {
        double x = velocity[from + static_cast<std::size_t>(a)];
        velocity[from + static_cast<std::size_t>(a)] = 0.0;
        if constexpr (kAdded) x += added[from + static_cast<std::size_t>(a)];
        check += x;
        active[static_cast<std::size_t>(K * s + a)] = x;
      }
    }
    return std::isfinite(check);
  }
}

template <int K>
bool GatherActive(const int* id, int n, double* velocity, const double* added, double* active) {
  return added == nullptr ? GatherActive<K, false>(id, n, velocity, nullptr, active)
                          : GatherActive<K, true>(id, n, velocity, added, active);
}

}  // namespace

// Each thread gathers a contiguous range of slots (the ids are distinct, so no two write the
// same value); the verdict is exact whatever the split (see GatherActive).
int ParticleStore::TakeActive(std::span<double> velocity, std::span<const double> added,
                              int threads) {
  MOREAU_ASSERT(velocity.size() == current.size() &&
                (added.empty() || added.size() == current.size()));
  active.resize(current.size());
  const int parts = n >= 16384 ? std::max(1, threads) : 1;
  const double* plus = added.empty() ? nullptr : added.data();
  bool finite = true;
#pragma omp parallel for num_threads(parts) schedule(static) reduction(&& : finite)
  for (int part = 0; part < parts; ++part) {
    const int lo = static_cast<int>(static_cast<std::int64_t>(n) * part / parts);
    const int hi = static_cast<int>(static_cast<std::int64_t>(n) * (part + 1) / parts);
    double* out = active.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(lo);
    finite = (k == 2 ? GatherActive<2>(id.data() + lo, hi - lo, velocity.data(), plus, out)
                     : GatherActive<3>(id.data() + lo, hi - lo, velocity.data(), plus, out)) &&
             finite;
  }
  if (finite) return -1;
  int lowest = -1;  // the exact check: the lowest id, whatever the storage order
  for (int s = 0; s < n; ++s) {
    for (int a = 0; a < k; ++a) {
      if (std::isfinite(active[static_cast<std::size_t>(k * s + a)])) continue;
      const int i = id[static_cast<std::size_t>(s)];
      if (lowest < 0 || i < lowest) lowest = i;
    }
  }
  return lowest;
}

}  // namespace moreau::particles::internal
