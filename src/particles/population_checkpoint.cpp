// Population::SaveState / RestoreState (checkpoint.h): the agents, their variables, the counters
// and the engine's state; the engine takes the saved roster first (Repopulate), then its state.
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/checkpoint.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

namespace {

// A state that does not fit a population of these rules: InputError "checkpoint: …".
void CheckPopulationState(const PopulationState& s, const PopulationRules& rules, int k) {
  const std::size_t n = s.agents.size();
  if (n == 0) throw InputError("checkpoint: a population state needs at least one agent");
  if (static_cast<std::size_t>(s.engine.count) != n || s.engine.dimension != k) {
    throw InputError(fmt::format("checkpoint: {} agents but an engine of {} particles in {}D", n,
                                 s.engine.count, s.engine.dimension));
  }
  std::unordered_set<std::int64_t> ids;
  for (const Agent& a : s.agents) {
    if (a.type < 0 || static_cast<std::size_t>(a.type) >= rules.types.size() || !(a.radius > 0.0) ||
        !std::isfinite(a.radius) || !ids.insert(a.id).second) {
      throw InputError(fmt::format("checkpoint: agent {} has a bad type, radius or id", a.id));
    }
  }
  if (s.variables.size() != rules.variables.size()) {
    throw InputError(fmt::format("checkpoint: {} user variables, the rules declare {}",
                                 s.variables.size(), rules.variables.size()));
  }
  for (const std::vector<double>& v : s.variables) {
    if (v.size() != n) throw InputError("checkpoint: a user variable does not fit the agents");
  }
}

}  // namespace

PopulationState Population::SaveState() const {
  PopulationState s;
  s.engine = engine_.SaveState();
  s.agents = agents_;
  s.variables = variables_;
  s.last_positions = last_positions_;
  s.last_deaths = last_deaths_;
  s.last_removals = last_removals_;
  s.counters = summary_;
  s.counters.engine = {};
  s.counters.settings = {};
  s.overlap_before = overlap_before_;
  s.stopped = stopped_;
  return s;
}

void Population::RestoreState(const PopulationState& s) {
  const int k = geometry_.dimension;
  CheckPopulationState(s, rules_, k);
  const auto uk = static_cast<std::size_t>(k);
  // The saved positions in index order, for the roster's first build (the engine's state then
  // replaces it): slot q holds particle slot_ids[q].
  std::vector<double> x(s.engine.current.size());
  if (s.engine.slot_ids.size() * uk != x.size()) {
    throw InputError("checkpoint: array sizes do not match the particle count");
  }
  for (std::size_t q = 0; q < s.engine.slot_ids.size(); ++q) {
    const int id = s.engine.slot_ids[q];
    if (id < 0 || static_cast<std::size_t>(id) >= s.agents.size()) {
      throw InputError("checkpoint: slot_ids is not a permutation of the particle ids");
    }
    for (std::size_t a = 0; a < uk; ++a)
      x[uk * static_cast<std::size_t>(id) + a] = s.engine.current[uk * q + a];
  }
  agents_ = s.agents;
  variables_ = s.variables;
  ids_.clear();
  for (const Agent& a : agents_) ids_.insert(a.id);
  motility_ = ActiveVelocities();
  drifting_ = false;
  engine_.Repopulate(ModelOf(geometry_, rules_, agents_), x, motility_);
  engine_.RestoreState(s.engine);
  last_positions_ = s.last_positions;
  last_deaths_ = s.last_deaths;
  last_removals_ = s.last_removals;
  const PopulationRules settings = summary_.settings;
  summary_ = s.counters;
  summary_.settings = settings;
  overlap_before_ = s.overlap_before;
  stopped_ = s.stopped;
}

}  // namespace moreau::particles
