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

// The fields' values and the samples (the state's agents are already in place).
void Population::RestoreFields(const PopulationState& s) {
  const auto substrates = static_cast<std::size_t>(fields_->substrate_count());
  const std::size_t n = agents_.size(), k = static_cast<std::size_t>(geometry_.dimension);
  bool fits = s.field_values.size() == substrates && s.field_samples.size() == substrates &&
              s.field_gradients.size() == substrates;
  for (std::size_t f = 0; fits && f < substrates; ++f) {
    fits = s.field_samples[f].size() == n && s.field_gradients[f].size() == k * n;
  }
  if (!fits) throw InputError("checkpoint: the fields' state does not fit the population's fields");
  fields_->Restore(s.field_values, s.field_time, s.field_steps);
  field_samples_ = s.field_samples;
  field_gradients_ = s.field_gradients;
  samples_current_ = true;
}

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
  if (fields_) {
    for (int f = 0; f < fields_->substrate_count(); ++f) {
      const std::span<const double> v = fields_->values(f);
      s.field_values.emplace_back(v.begin(), v.end());
    }
    s.field_samples = field_samples_;
    s.field_gradients = field_gradients_;
    s.field_time = fields_->time();
    s.field_steps = fields_->steps();
  }
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
  if (fields_) RestoreFields(s);
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
