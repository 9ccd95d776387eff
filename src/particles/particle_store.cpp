#include "particles/particle_store.h"

#include <algorithm>
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
  slot_of = id;
  uniform_radius_ = std::all_of(radius.begin(), radius.end(),
                                [&](double r) { return r == radius.front(); });
  uniform_mobility_ = std::all_of(mobility.begin(), mobility.end(),
                                  [&](double m) { return m == mobility.front(); });
}

// One pass over the slots gathers every per-slot array (radius and mobility only when they
// differ between particles: a uniform array is the same in any order).
void ParticleStore::Reorder(const std::vector<int>& perm, int threads) {
  const auto entries = static_cast<std::size_t>(k) * static_cast<std::size_t>(n);
  const bool gather_radius = !uniform_radius_;
  const bool gather_mobility = !uniform_mobility_;
  const bool has_key = !noise_key.empty();
  const bool has_active = !active.empty();
  scratch_current_.resize(entries);
  scratch_predicted_.resize(entries);
  if (has_active) scratch_active_.resize(entries);
  if (gather_radius) scratch_radius_.resize(static_cast<std::size_t>(n));
  if (gather_mobility) scratch_mobility_.resize(static_cast<std::size_t>(n));
  if (has_key) scratch_key_.resize(noise_key.size());
  scratch_id_.resize(id.size());
  const int kk = k;
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int s = 0; s < n; ++s) {
    const auto us = static_cast<std::size_t>(s);
    const auto o = static_cast<std::size_t>(perm[us]);
    for (int a = 0; a < kk; ++a) {
      scratch_current_[kk * us + a] = current[kk * o + a];
      scratch_predicted_[kk * us + a] = predicted[kk * o + a];
      if (has_active) scratch_active_[kk * us + a] = active[kk * o + a];
    }
    if (gather_radius) scratch_radius_[us] = radius[o];
    if (gather_mobility) scratch_mobility_[us] = mobility[o];
    if (has_key) scratch_key_[us] = noise_key[o];
    const int i = id[o];
    scratch_id_[us] = i;
    slot_of[static_cast<std::size_t>(i)] = s;
  }
  current.swap(scratch_current_);
  predicted.swap(scratch_predicted_);
  if (has_active) active.swap(scratch_active_);
  if (gather_radius) radius.swap(scratch_radius_);
  if (gather_mobility) mobility.swap(scratch_mobility_);
  if (has_key) noise_key.swap(scratch_key_);
  id.swap(scratch_id_);
}

void ParticleStore::CopyPositionsById(const PeriodicBox& box, std::span<double> out,
                                      int threads) const {
  MOREAU_ASSERT(out.size() == current.size());
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int s = 0; s < n; ++s) {
    const int i = id[static_cast<std::size_t>(s)];
    for (int a = 0; a < k; ++a) {
      double v = current[static_cast<std::size_t>(k * s + a)];
      if (box.periodic[a]) v = Wrap(v, box.lo[a], box.len[a]);
      out[static_cast<std::size_t>(k * i + a)] = v;
    }
  }
}

}  // namespace moreau::particles::internal
