// The population's rule step (population.h) on top of the engine.
#include "moreau/particles/population.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/common/steps.h"
#include "moreau/common/stopwatch.h"

namespace moreau::particles {

namespace {

// One stream of randomness per rule: the rule seed is mixed with the stream's constant.
enum class Stream : std::uint64_t {
  kDeath = 0x6a09e667f3bcc908ULL,
  kDivision = 0xbb67ae8584caa73bULL,
  kAxis = 0x3c6ef372fe94f82bULL,
  kPolarity = 0xa54ff53a5f1d36f1ULL,
};

std::uint64_t StreamSeed(std::uint64_t seed, Stream stream) {
  return seed ^ static_cast<std::uint64_t>(stream);
}

// A uniform in (0, 1) for (seed, stream, id, step).
double Uniform(std::uint64_t seed, Stream stream, std::int64_t id, std::int64_t step) {
  const std::uint64_t key = StreamSeed(seed, stream);
  const auto uid = static_cast<std::uint64_t>(id);
  const auto ustep = static_cast<std::uint64_t>(step);
  const auto w =
      Philox4x32({static_cast<std::uint32_t>(uid), static_cast<std::uint32_t>(uid >> 32),
                  static_cast<std::uint32_t>(ustep), static_cast<std::uint32_t>(ustep >> 32)},
                 {static_cast<std::uint32_t>(key), static_cast<std::uint32_t>(key >> 32)});
  const std::uint64_t a = (static_cast<std::uint64_t>(w[0]) << 32 | w[1]) >> 11;
  return (static_cast<double>(a) + 0.5) * 0x1.0p-53;
}

// Normalises the first k components of v; false (v unchanged) when its norm is 0 or not finite.
bool Normalise(int k, double* v) {
  double n2 = 0.0;
  for (int a = 0; a < k; ++a) n2 += v[a] * v[a];
  const double norm = std::sqrt(n2);
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  for (int a = 0; a < k; ++a) v[a] /= norm;
  return true;
}

}  // namespace

ParticleModel Population::ModelOf(const ParticleModel& geometry, const PopulationRules& rules,
                                  const std::vector<Agent>& agents) {
  ParticleModel model = geometry;
  const std::size_t n = agents.size();
  model.radius.resize(n);
  model.mobility.resize(n);
  model.stable_ids.resize(n);
  model.adhesion_class.resize(n);  // the type: the row and column of the adhesion matrix
  for (std::size_t i = 0; i < n; ++i) {
    model.radius[i] = agents[i].radius;
    model.mobility[i] = rules.types[static_cast<std::size_t>(agents[i].type)].mobility;
    model.stable_ids[i] = agents[i].id;
    model.adhesion_class[i] = agents[i].type;
  }
  return model;
}

namespace {

std::vector<Agent> InitialAgents(const PopulationRules& rules, int k, std::span<const int> types,
                                 std::uint64_t seed) {
  rules.Validate();
  std::vector<Agent> agents(types.size());
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (types[i] < 0 || static_cast<std::size_t>(types[i]) >= rules.types.size()) {
      throw InputError(fmt::format("type of agent {} must be in [0, {}) (got {})", i,
                                   rules.types.size(), types[i]));
    }
    Agent& a = agents[i];
    a.id = static_cast<std::int64_t>(i);
    a.type = types[i];
    a.radius = rules.types[static_cast<std::size_t>(a.type)].radius;
    // The initial polarity: uniformly random on the unit circle/sphere.
    double p[3] = {0, 0, 0};
    GaussianNoise(StreamSeed(seed, Stream::kPolarity), a.id, -1, k, p);
    if (!Normalise(k, p)) p[0] = 1.0;
    for (int c = 0; c < k; ++c) a.polarity[static_cast<std::size_t>(c)] = p[c];
  }
  return agents;
}

}  // namespace

Population::Population(ParticleModel geometry, Forces forces, EngineOptions options,
                       PopulationRules rules, std::span<const int> types,
                       std::span<const double> positions)
    : geometry_(std::move(geometry)),
      rules_(std::move(rules)),
      agents_(InitialAgents(rules_, geometry_.dimension, types, rules_.seed)),
      engine_(ModelOf(geometry_, rules_, agents_), rules_.WithAdhesion(std::move(forces)), options,
              positions),
      last_positions_(positions.begin(), positions.end()) {
  for (const Agent& a : agents_) ids_.insert(a.id);
  for (const AgentVariable& v : rules_.variables)
    variables_.emplace_back(agents_.size(), v.initial);
  motility_ = ActiveVelocities();
  if (!motility_.empty()) {
    engine_.Repopulate(ModelOf(geometry_, rules_, agents_), positions, motility_);
  }
  summary_.settings = rules_;
  summary_.final_count = count();
}

std::vector<double> Population::ActiveVelocities() const {
  const int k = geometry_.dimension;
  bool any = false;
  for (const AgentType& t : rules_.types) any = any || t.speed > 0.0;
  const bool chemotaxis = HasChemotaxis();
  if (!any && !chemotaxis) return {};
  std::vector<double> v(static_cast<std::size_t>(k) * agents_.size());
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    const double speed = rules_.types[static_cast<std::size_t>(agents_[i].type)].speed;
    for (int a = 0; a < k; ++a) {
      v[static_cast<std::size_t>(k) * i + static_cast<std::size_t>(a)] =
          speed * agents_[i].polarity[static_cast<std::size_t>(a)];
    }
  }
  if (chemotaxis) AddFieldDrift(&v);  // χ ∇c / (1 + |∇c|/g), population_fields.h
  return v;
}

// Per agent the mean polarity of the agents touching it (the engine's contacts, periodic
// images included), or its own polarity when none does.
std::vector<double> Population::MeanNeighbourPolarity() const {
  const auto k = static_cast<std::size_t>(geometry_.dimension);
  std::vector<double> sum(k * agents_.size(), 0.0);
  std::vector<int> touching(agents_.size(), 0);
  for (const auto& [i, j] : engine_.Contacts(rules_.contact_factor)) {
    const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
    for (std::size_t a = 0; a < k; ++a) {
      sum[k * ui + a] += agents_[uj].polarity[a];
      sum[k * uj + a] += agents_[ui].polarity[a];
    }
    ++touching[ui];
    ++touching[uj];
  }
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    for (std::size_t a = 0; a < k; ++a) {
      sum[k * i + a] = touching[i] > 0 ? sum[k * i + a] / touching[i] : agents_[i].polarity[a];
    }
  }
  return sum;
}

// The polarity rule of population.h for agent i (index in the old roster).
void Population::UpdatePolarity(std::size_t i, std::span<const double> x,
                                std::span<const double> mean, Agent* agent) const {
  const AgentType& type = rules_.types[static_cast<std::size_t>(agent->type)];
  const int k = geometry_.dimension;
  const auto uk = static_cast<std::size_t>(k);
  const double dt = static_cast<double>(rules_.interval) * engine_.options().h;
  double p[3] = {0, 0, 0};
  for (int a = 0; a < k; ++a) p[a] = agent->polarity[static_cast<std::size_t>(a)];
  double next[3] = {p[0], p[1], p[2]};
  if (type.alignment > 0.0) {
    for (std::size_t a = 0; a < uk; ++a) next[a] += dt * type.alignment * (mean[uk * i + a] - p[a]);
  }
  if (type.velocity_alignment > 0.0) {
    double v[3] = {0, 0, 0};
    for (std::size_t a = 0; a < uk; ++a) v[a] = x[uk * i + a] - last_positions_[uk * i + a];
    if (Normalise(k, v)) {
      for (int a = 0; a < k; ++a) next[a] += dt * type.velocity_alignment * (v[a] - p[a]);
    }
  }
  if (type.persistence_time > 0.0) {
    double eta[3] = {0, 0, 0};
    GaussianNoise(StreamSeed(rules_.seed, Stream::kPolarity), agent->id, engine_.step(), k, eta);
    double along = 0.0;
    for (int a = 0; a < k; ++a) along += eta[a] * p[a];
    const double sigma = std::sqrt(2.0 * dt / type.persistence_time);
    for (int a = 0; a < k; ++a) next[a] += sigma * (eta[a] - along * p[a]);
  }
  if (Normalise(k, next)) {
    for (int a = 0; a < k; ++a) agent->polarity[static_cast<std::size_t>(a)] = next[a];
  }
}

void Population::Stop(Termination termination, std::string message) {
  stopped_ = true;
  summary_.termination = termination;
  summary_.message = std::move(message);
}

// Agent `id` leaves now: counted as a removal or a death, listed, its id released.
void Population::Depart(std::int64_t id, bool removed) {
  ++(removed ? summary_.removals : summary_.deaths);
  (removed ? last_removals_ : last_deaths_).push_back(id);
  ids_.erase(id);
}

// The removal and death rules: true (counted, the id released) when agent a leaves now.
bool Population::Leaves(const Agent& a, const double* xi, std::int64_t step) {
  const AgentType& type = rules_.types[static_cast<std::size_t>(a.type)];
  const double dt = static_cast<double>(rules_.interval) * engine_.options().h;
  bool removed = false;
  if (rules_.exit) {
    double along = 0.0;
    for (int c = 0; c < geometry_.dimension; ++c) {
      along += rules_.exit->normal[static_cast<std::size_t>(c)] * xi[c];
    }
    removed = along > rules_.exit->offset;
  }
  const bool dies =
      !removed && type.death_rate > 0.0 &&
      Uniform(rules_.seed, Stream::kDeath, a.id, step) < -std::expm1(-type.death_rate * dt);
  if (!removed && !dies) return false;
  Depart(a.id, removed);
  return true;
}

// The division rule of population.h: agent a (state after growth and polarity) at xi splits
// into itself and a new daughter, appended to *next with their positions to *y.
void Population::Divide(Agent a, const double* xi, std::int64_t step, std::vector<Agent>* next,
                        std::vector<double>* y) {
  const int k = geometry_.dimension;
  const auto uk = static_cast<std::size_t>(k);
  const AgentType& type = rules_.types[static_cast<std::size_t>(a.type)];
  double e[3] = {0, 0, 0};
  if (rules_.axis == DivisionAxis::kPolarity) {
    for (int c = 0; c < k; ++c) e[c] = a.polarity[static_cast<std::size_t>(c)];
  }
  if (rules_.axis == DivisionAxis::kRandom || !Normalise(k, e)) {
    GaussianNoise(StreamSeed(rules_.seed, Stream::kAxis), a.id, step, k, e);
    if (!Normalise(k, e)) e[0] = 1.0;
  }
  ++a.divisions;
  ++a.generation;
  a.age = 0.0;
  a.radius = type.radius;
  Agent daughter = a;
  daughter.id = ChildId(a.id, a.divisions);
  daughter.divisions = 0;
  daughter.mother = a.id;
  if (!ids_.insert(daughter.id).second) {
    throw NumericalError(
        fmt::format("step {}: the daughter id {} of agent {} is in use (a hash "
                    "collision)",
                    step, daughter.id, a.id));
  }
  for (const auto& [agent, sign] : {std::pair{a, 1.0}, std::pair{daughter, -1.0}}) {
    next->push_back(agent);
    for (std::size_t c = 0; c < uk; ++c) y->push_back(xi[c] + sign * type.radius * e[c]);
  }
}

// The type's division rules for agent a (after growth), contact inhibition aside.
bool Population::Divides(const Agent& a, const AgentType& type, std::int64_t step,
                         double dt) const {
  return (type.division_radius > 0.0 && a.radius >= type.division_radius) ||
         (type.cycle_time > 0.0 && a.age >= type.cycle_time) ||
         (type.division_rate > 0.0 && Uniform(rules_.seed, Stream::kDivision, a.id, step) <
                                          -std::expm1(-type.division_rate * dt));
}

// growth → removal → death → polarity → division, agent by agent (population.h); then the
// engine takes the new roster.
void Population::ApplyRules() {
  const Stopwatch stopwatch;
  const int k = geometry_.dimension;
  const auto uk = static_cast<std::size_t>(k);
  const double dt = static_cast<double>(rules_.interval) * engine_.options().h;
  const std::int64_t step = engine_.step();
  const std::span<const double> x = CurrentPositions();  // shared with the user rule's view
  bool aligns = false, inhibits = false;
  for (const AgentType& t : rules_.types) {
    aligns = aligns || t.alignment > 0.0;
    inhibits = inhibits || t.max_contacts > 0.0;
  }
  if (fields_) StepFields(x, dt);  // deposit, step, sample: before the rules read the samples
  std::vector<std::uint8_t> divide, die;
  if (rule_) ApplyUserRule(&divide, &die);
  rules_pending_ = false;  // from here on nothing is redone: an error stops or is final
  const std::vector<double> mean = aligns ? MeanNeighbourPolarity() : std::vector<double>{};
  const std::vector<int> contacts =
      inhibits ? engine_.ContactCounts(rules_.contact_factor) : std::vector<int>{};
  std::vector<Agent> next;
  std::vector<double> y;
  std::vector<std::vector<double>> next_variables(variables_.size());
  next.reserve(agents_.size() + agents_.size() / 4 + 1);
  y.reserve(uk * next.capacity());
  std::int64_t births = 0;
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    Agent a = agents_[i];
    bool starved = false;  // below a proliferation threshold
    if (fields_ && FieldFate(i, &a, &starved)) {
      Depart(a.id, false);  // necrosis
      continue;
    }
    const AgentType& type = rules_.types[static_cast<std::size_t>(a.type)];
    const double* xi = x.data() + uk * i;
    const bool inhibited = starved || (type.max_contacts > 0.0 &&
                                       static_cast<double>(contacts[i]) >= type.max_contacts);
    if (!inhibited) a.radius += type.growth_rate * dt;
    a.age += dt;
    if (!die.empty() && die[i] != 0) {  // the user rule's death
      Depart(a.id, false);
      continue;
    }
    if (Leaves(a, xi, step)) continue;
    UpdatePolarity(i, x, mean, &a);
    const bool divides =
        (!divide.empty() && divide[i] != 0) || (!inhibited && Divides(a, type, step, dt));
    Inherit(i, divides, &next_variables);
    if (!divides) {
      next.push_back(a);
      y.insert(y.end(), xi, xi + uk);
      continue;
    }
    Divide(a, xi, step, &next, &y);
    ++births;
  }
  summary_.births += births;
  positions_current_ = false;
  agents_.swap(next);
  variables_.swap(next_variables);
  ++summary_.rule_steps;
  summary_.final_count = count();
  if (agents_.empty()) {
    summary_.rules_seconds += stopwatch.Seconds();
    Stop(Termination::kCompleted, fmt::format("no agents left at step {}", step));
    return;
  }
  samples_current_ = false;  // the samples are the old roster's until AfterRepopulate
  motility_ = ActiveVelocities();
  engine_.Repopulate(ModelOf(geometry_, rules_, agents_), y, motility_);
  AfterRepopulate();
  summary_.rules_seconds += stopwatch.Seconds();
  if (rules_.max_count > 0 && count() >= rules_.max_count) {
    Stop(Termination::kCompleted, fmt::format("the count reached {} (max_count {}) at step {}",
                                              count(), rules_.max_count, step));
  }
}

// The overlap right after the repopulation, the relaxation, the positions velocity alignment
// reads, and with fields the samples at the new positions and the chemotaxis they give.
void Population::AfterRepopulate() {
  overlap_before_ = engine_.MaxPairOverlap();
  summary_.max_overlap_before = std::max(summary_.max_overlap_before, overlap_before_);
  if (rules_.relax) {
    double rmin = rules_.types.front().radius;
    for (const AgentType& t : rules_.types) rmin = std::min(rmin, t.radius);
    summary_.relax_sweeps += engine_.Relax(rules_.relax_tolerance * rmin, rules_.relax_max_sweeps);
  }
  bool follows_velocity = false;
  for (const AgentType& t : rules_.types) follows_velocity |= t.velocity_alignment > 0.0;
  if (follows_velocity) last_positions_ = engine_.Positions();
  if (!fields_) return;
  SampleFields();
  if (!HasChemotaxis()) return;
  motility_ = ActiveVelocities();
  engine_.SetActiveVelocities(motility_);
}

bool Population::Step() {
  if (stopped_) return false;
  const Stopwatch stopwatch;
  try {
    if (rules_pending_) ApplyRules();  // the last step's user rule threw: its rule step first
    if (!stopped_) StepOnce();
  } catch (const NumericalError& e) {
    Stop(Termination::kNonFinite, e.what());
  }
  summary_.total_seconds += stopwatch.Seconds();
  return !stopped_;
}

// The drift, one engine step and, at a multiple of the interval, the rules.
void Population::StepOnce() {
  if (drift_) {
    ApplyDrift();
    drifting_ = true;
  } else if (drifting_) {  // the drift was removed: the motility alone again
    engine_.SetActiveVelocities(motility_);
    drifting_ = false;
  }
  const bool stepped = engine_.Step();
  positions_current_ = false;
  if (!stepped) {
    Stop(Termination::kNonFinite, engine_.summary().message);
    return;
  }
  if (engine_.step() % rules_.interval == 0) {
    last_deaths_.clear();
    last_removals_.clear();
    rules_pending_ = true;  // until the user rule has returned (it may throw)
    ApplyRules();
  }
}

PopulationSummary Population::Run(double T, const PopulationObserver& observer) {
  const std::int64_t steps = StepCount(T, engine_.options().h);
  if (observer && !observer(*this)) Stop(Termination::kInterrupted, "stopped by the observer");
  return RunTo(engine_.step() + steps, observer);
}

PopulationSummary Population::Continue(double T, const PopulationObserver& observer) {
  return RunTo(StepCount(T, engine_.options().h), observer);
}

PopulationSummary Population::RunTo(std::int64_t last_step, const PopulationObserver& observer) {
  while (engine_.step() < last_step && !stopped_) {
    const std::int64_t rules_before = summary_.rule_steps;
    Step();
    if (observer && summary_.rule_steps > rules_before && !agents_.empty() && !observer(*this) &&
        !stopped_) {
      Stop(Termination::kInterrupted, "stopped by the observer");
    }
  }
  return summary();
}

PopulationObservables Population::Observe() const {
  PopulationObservables o;
  o.step = engine_.step();
  o.time = engine_.time();
  o.count_per_type.assign(rules_.types.size(), 0);
  o.count = count();
  o.births = summary_.births;
  o.deaths = summary_.deaths;
  o.removals = summary_.removals;
  o.overlap_before = overlap_before_;
  if (agents_.empty()) return o;
  const auto k = static_cast<std::size_t>(geometry_.dimension);
  const std::vector<double> x = engine_.Positions();
  double centre[3] = {0, 0, 0};
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    ++o.count_per_type[static_cast<std::size_t>(agents_[i].type)];
    o.mean_radius += agents_[i].radius;
    for (std::size_t a = 0; a < k; ++a) centre[a] += x[k * i + a];
  }
  const auto n = static_cast<double>(agents_.size());
  o.mean_radius /= n;
  for (std::size_t a = 0; a < k; ++a) centre[a] /= n;
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    double d2 = 0.0;
    for (std::size_t a = 0; a < k; ++a)
      d2 += (x[k * i + a] - centre[a]) * (x[k * i + a] - centre[a]);
    o.colony_radius = std::max(o.colony_radius, std::sqrt(d2) + agents_[i].radius);
  }
  const std::vector<std::pair<int, int>> contacts = engine_.Contacts(rules_.contact_factor);
  o.contacts = static_cast<std::int64_t>(contacts.size());
  std::vector<int> types(agents_.size());
  for (std::size_t i = 0; i < agents_.size(); ++i) types[i] = agents_[i].type;
  o.segregation = SegregationIndex(types, contacts);
  o.overlap = engine_.MaxPairOverlap();
  return o;
}

PopulationSummary Population::summary() const {
  PopulationSummary s = summary_;
  s.engine = engine_.summary();
  s.final_count = count();
  return s;
}

}  // namespace moreau::particles
