// Engine::SaveState / RestoreState (checkpoint.h): the storage order, the positions, the last
// neighbour-list build (its positions, skin, bound and the cell grid's fit) and the counters.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/checkpoint.h"
#include "particles/engine_impl.h"

namespace moreau::particles {

namespace {

void CheckState(const EngineState& s, int k, int n) {
  if (s.dimension != k || s.count != n) {
    throw InputError(fmt::format("checkpoint: {} particles in {}D, the run has {} in {}D", s.count,
                                 s.dimension, n, k));
  }
  const auto entries = static_cast<std::size_t>(k) * static_cast<std::size_t>(n);
  if (s.slot_ids.size() != static_cast<std::size_t>(n) || s.current.size() != entries ||
      s.reference.size() != entries) {
    throw InputError("checkpoint: array sizes do not match the particle count");
  }
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (int id : s.slot_ids) {
    if (id < 0 || id >= n || seen[static_cast<std::size_t>(id)]) {
      throw InputError("checkpoint: slot_ids is not a permutation of the particle ids");
    }
    seen[static_cast<std::size_t>(id)] = 1;
  }
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!std::all_of(s.current.begin(), s.current.end(), finite) ||
      !std::all_of(s.reference.begin(), s.reference.end(), finite) || !(s.skin > 0.0) ||
      !std::isfinite(s.skin) || !(s.drift_bound >= 0.0) || !(s.grid_reach > 0.0) || s.step < 0) {
    throw InputError("checkpoint: non-finite or out-of-range values");
  }
}

}  // namespace

void Engine::Impl::Restore(const EngineState& s) {
  internal::StepContext& c = context;
  CheckState(s, c.k, c.n);
  std::vector<int> perm(static_cast<std::size_t>(c.n));
  const std::vector<int> slot_of = c.store->SlotsOf();
  for (std::size_t q = 0; q < perm.size(); ++q) {
    perm[q] = slot_of[static_cast<std::size_t>(s.slot_ids[q])];
  }
  c.store->Reorder(perm, c.threads);
  prediction->Reorder(perm, c.threads);
  // The last build again: same positions, slots, skin and grid give the same list and order.
  internal::NeighbourListState ls{s.skin, s.drift_bound, s.last_build_step, {}};
  ls.stats = {s.stats.neighbour_list_builds, s.stats.candidate_pairs, s.shortest_rebuild_interval};
  c.list.Restore(ls);
  internal::CellList::FitRecord fit;
  std::copy(s.grid_lo, s.grid_lo + 3, fit.lo);
  std::copy(s.grid_hi, s.grid_hi + 3, fit.hi);
  fit.reach = s.grid_reach;
  c.cells.Refit(fit, c.n, c.box, c.options.block_cells);
  c.colouring.Assign(c.cells);
  std::vector<double> at = s.reference;
  c.cells.Sort(at.data(), c.store->id.data(), c.n, c.threads);
  const std::vector<int>& order = c.cells.permutation();
  if (!c.lexicographic) {
    for (int q = 0; q < c.n; ++q) {
      if (order[static_cast<std::size_t>(q)] != q) {
        throw InputError("checkpoint: the storage order does not match its neighbour-list build");
      }
    }
  }
  c.list.Build(c, at.data(), s.last_build_step);
  c.list.Restore(ls);
  c.store->current = s.current;
  step = s.step;
  stats = s.stats;
  profile = internal::StageProfile::Of(s.stats);
}

EngineState Engine::SaveState() const {
  const Impl& m = *impl_;
  const internal::StepContext& c = m.context;
  EngineState s;
  s.dimension = c.k;
  s.count = c.n;
  s.step = m.step;
  s.slot_ids = c.store->id;
  s.current = c.store->current;
  s.reference = c.list.reference();
  const internal::NeighbourListState ls = c.list.State();
  s.skin = ls.skin;
  s.drift_bound = ls.drift_bound;
  s.last_build_step = ls.last_build_step;
  s.shortest_rebuild_interval = ls.stats.shortest_rebuild_interval;
  const internal::CellList::FitRecord& fit = c.cells.fit();
  std::copy(fit.lo, fit.lo + 3, s.grid_lo);
  std::copy(fit.hi, fit.hi + 3, s.grid_hi);
  s.grid_reach = fit.reach;
  s.stats = m.Stats();
  return s;
}

void Engine::RestoreState(const EngineState& state) {
  if (impl_->termination != Termination::kCompleted) {
    throw InputError("checkpoint: the engine has failed already");
  }
  impl_->Restore(state);
}

}  // namespace moreau::particles
