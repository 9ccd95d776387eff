// The engine's particle storage: per slot the current and predicted positions, radius, mobility
// and particle id. The slots are reordered along the cell list's Morton curve at neighbour-list
// builds (coloured sweep order); ids travel with them, so results can be read in id order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "particles/kernels.h"

namespace moreau::particles::internal {

struct ParticleStore {
  int k = 2;
  int n = 0;
  std::vector<double> current;    // k per slot: X at the last accepted step (unwrapped between
                                  // builds on periodic axes)
  std::vector<double> predicted;  // k per slot: Y, then the sweep's result
  std::vector<double> radius;
  std::vector<double> mobility;
  std::vector<int> id;                  // particle id of each slot
  std::vector<std::int64_t> noise_key;  // per slot, the model's stable id; empty: the id
  std::vector<double> active;           // k per slot, an active velocity v_i; empty: none

  // Slots in id order, positions from `positions` (k·N, id order), active velocities from
  // `active` (k·N, id order, or empty).
  ParticleStore(const ParticleModel& model, std::span<const double> positions,
                std::span<const double> active = {});
  // New slot s holds old slot perm[s] (positions, radius, mobility, ids, keys, velocities).
  // with_current false: the current positions stay in the old order until GatherCurrent(perm)
  // (a build at the predicted positions needs them only for a redo).
  // copied, copy (optional): &current or &predicted, whose rows in the new order are also written
  // to copy (k per slot).
  void Reorder(const std::vector<int>& perm, int threads, bool with_current = true,
               const std::vector<double>* copied = nullptr, double* copy = nullptr);
  void GatherCurrent(const std::vector<int>& perm, int threads);
  // The slot of each particle id (the inverse of id).
  std::vector<int> SlotsOf() const;
  // The current positions in id order, wrapped into the periodic domain; out: size k·N.
  void CopyPositionsById(const PeriodicBox& box, std::span<double> out, int threads) const;
  // active = velocity + added in slot order (both k·N, id order; added may be empty), in one
  // pass that also zeroes velocity (on `threads` threads for large n). Returns −1 when every sum
  // is finite, else the lowest id whose sum is not (active is written either way).
  int TakeActive(std::span<double> velocity, std::span<const double> added, int threads);

 private:
  bool uniform_radius_ = false;  // every radius equal (then Reorder leaves the array alone)
  bool uniform_mobility_ = false;
  std::vector<double> scratch1_, scratch_k_, scratch_current_;
  std::vector<int> scratch_id_;
  std::vector<std::int64_t> scratch_key_;
};

}  // namespace moreau::particles::internal
