// Agent-based models on the particle engine: a population of agents (cells, pedestrians) that
// grow, divide, die or leave, carry a polarity and move along it, between the engine's steps.
//
// Agents are the engine's particles; each has a stable id, a type (per-type parameters below),
// a generation, a division count, an age, a radius and a unit polarity p_i. Every `interval`
// engine steps (the rule step, Δt = interval · h, at step s = interval, 2·interval, …) the rules
// act on every agent i, in this order, with randomness drawn by Philox4x32 keyed by
// (seed, stable id, s) and a stream per rule — so an agent's fate depends only on
// (seed, id, step) and its own state, never on threads or the order agents are processed:
//   growth      r_i ← r_i + g Δt (only while c_i < c_max: contact inhibition, c_i the number
//               of agents touching i);  age_i ← age_i + Δt;
//   removal     removed when its centre is past the exit plane, ⟨n, X_i⟩ > c (a crowd's exit);
//   death       dies with probability 1 − exp(−δ Δt);
//   polarity    p_i ← normalise(p_i + Δt [J (m_i − p_i) + β (v̂_i − p_i)] + √(2Δt/τ_p) P⊥ η_i),
//               m_i the mean polarity of the agents touching i (Vicsek-like alignment;
//               touching as Engine::Contacts says, across periodic boundaries too),
//               v̂_i the unit displacement of i over the last rule step (alignment with the
//               velocity), η_i ~ N(0, I) projected perpendicular to p_i (rotational diffusion,
//               persistence time τ_p; τ_p = 0: none). Alignment reads the previous polarities
//               (a Jacobi update), so the result is independent of the order;
//   division    (only while c_i < c_max) when r_i ≥ r_div (r_div > 0), or age_i ≥ τ_c
//               (τ_c > 0), or with probability 1 − exp(−λ Δt) (λ > 0). The mother keeps its
//               id; both daughters get radius r_0 (the type's radius), age 0, generation + 1,
//               and are placed at X_i ± r_0 e along a unit axis e (uniformly random, or the
//               polarity): they touch each other, and their overlaps with neighbours are
//               resolved by the projections (or at once by Engine::Relax when `relax` is set).
//               The new daughter's id is ChildId(mother's id, mother's division count after
//               this division), a pure function, so ids never depend on the order of events;
//   motility    the engine adds the active velocity v0 p_i to agent i's drift until the next rule
//               step (engine.h, Repopulate).
// Adhesion between touching agents is the engine's pair attraction (forces.h, PairAttraction):
// one stiffness k for all, or per pair of types k_ab (PopulationRules::adhesion, differential
// adhesion), the agent's type being its adhesion class (model.h).
// The new roster keeps the survivors in their previous order, each new daughter right after its
// mother; the engine then rebuilds its lists once (Engine::Repopulate).
//
// Ids: the initial agents have ids 0 … N0 − 1; ChildId mixes (id, count) into [0, 2^62) with a
// bijective 64-bit mixer, so two agents share an id only by a hash collision (probability
// ≈ N²/2^63, ~1e−9 at N = 10^5); the population checks this and stops with an error if it happens.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/enum_names.h"
#include "moreau/common/field_list.h"
#include "moreau/common/termination.h"
#include "moreau/fields/field_set.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/population_fields.h"

namespace moreau::particles {

// One agent type's parameters (times in the scenario's time unit, lengths in its length unit).
struct AgentType {
  std::string name = "cell";        // unique among the types
  double radius = 0.5;              // r_0 > 0: initial agents' and daughters' radius
  double growth_rate = 0.0;         // g ≥ 0: dr/dt (length/time)
  double division_radius = 0.0;     // r_div: divides at r ≥ r_div; 0: never by size; else > r_0
  double cycle_time = 0.0;          // τ_c ≥ 0: divides at age ≥ τ_c; 0: never by age
  double division_rate = 0.0;       // λ ≥ 0 (1/time): divides at rate λ
  double death_rate = 0.0;          // δ ≥ 0 (1/time)
  double mobility = 1.0;            // μ > 0, the engine's mobility
  double speed = 0.0;               // v0 ≥ 0: motility along the polarity (length/time)
  double persistence_time = 0.0;    // τ_p ≥ 0: polarity rotational diffusion 1/τ_p; 0: none
  double alignment = 0.0;           // J ≥ 0 (1/time): alignment with touching agents' polarity
  double velocity_alignment = 0.0;  // β ≥ 0 (1/time): alignment with the own velocity
  double max_contacts = 0.0;        // c_max, a whole number in [0, 1000]: contact inhibition,
                                    // grows and divides only while touching fewer than c_max
                                    // agents; 0: no inhibition

  // Every field (name, radius, …); the rule division_radius = 0 or > radius.
  static const FieldList<AgentType>& Fields();
};

enum class DivisionAxis { kRandom, kPolarity };
inline constexpr EnumNames<DivisionAxis, 2> kDivisionAxisNames{
    {{DivisionAxis::kRandom, "random"}, {DivisionAxis::kPolarity, "polarity"}}};
// "random", "polarity"; Parse throws InputError for other names.
std::string_view DivisionAxisName(DivisionAxis axis);
DivisionAxis ParseDivisionAxis(std::string_view name);

// Agents whose centre is past the plane, ⟨normal, X⟩ > offset, are removed.
struct ExitPlane {
  Vec3 normal{1.0, 0.0, 0.0};  // non-zero
  double offset = 0.0;
};

// A user variable: one number per agent (a concentration, a clock, a mark), declared by name.
// At a division the daughters inherit it: kCopy, both keep the mother's value; kSplit, each gets
// half (an amount shared between the two).
enum class Inheritance { kCopy, kSplit };
inline constexpr EnumNames<Inheritance, 2> kInheritanceNames{
    {{Inheritance::kCopy, "copy"}, {Inheritance::kSplit, "split"}}};
struct AgentVariable {
  std::string name;      // unique among the variables, not empty
  double initial = 0.0;  // the initial agents' value (finite)
  Inheritance inherit = Inheritance::kCopy;
};

struct PopulationRules {
  std::vector<AgentType> types;          // ≥ 1; agents name their type by index
  std::vector<AgentVariable> variables;  // user variables, in this order
  int interval = 10;                     // engine steps per rule step, ≥ 1
  std::uint64_t seed = 1;  // key of the rules' randomness (the engine's noise has its own)
  DivisionAxis axis = DivisionAxis::kRandom;
  std::optional<ExitPlane> exit;  // removal on leaving through it
  double contact_factor = 1.05;  // agents touch when ‖X_i − X_j‖ ≤ f (r_i + r_j), f in [1, 1.5]
  bool relax = false;            // after every rule step, Engine::Relax until every pair
                                 // overlap ≤ relax_tolerance · min r_0 (or relax_max_sweeps)
  double relax_tolerance = 1e-3;  // > 0
  int relax_max_sweeps = 10000;   // ≥ 1
  std::int64_t max_count = 0;     // stop (completed) once the count reaches it; 0: no cap
  // Differential adhesion: the pair attraction's stiffness k_ab ≥ 0 (force per length, forces.h)
  // between agents of the types named a and b, one entry per unordered pair ((a, b) and (b, a)
  // are the same pair; giving both with different values is an error). Pairs not listed keep
  // the uniform stiffness k of Forces::attraction (0 without one). Needs Forces::attraction with
  // a range ℓ > 0, shared by all pairs. Scenario keys population.adhesion.<a>.<b>.
  std::map<std::pair<std::string, std::string>, double> adhesion;

  // The scalar fields (interval, seed, axis, contact_factor, relax, …); the types are addressed
  // by name, types.<name>.<key> with the keys of AgentType::Fields().
  static const FieldList<PopulationRules>& Fields();
  // Throws InputError(key, reason) naming the field: ("types.cell.growth_rate", "must be ≥ 0
  // (got -1)"), ("types", "the name 'cell' is used twice"), ("interval", "must be ≥ 1 (got 0)"),
  // ("adhesion.cell.tumor", "unknown type 'tumor' (types: cell, tumour)"), …
  void Validate() const;
  // The index of the type called `name`; InputError "unknown type 'x' (types: a, b)".
  int TypeIndex(std::string_view name) const;
  // The adhesion as the engine takes it: `forces` with its attraction's class matrix K
  // (T × T over the type indices, row-major) from `adhesion`, the pairs not listed at the
  // forces' uniform stiffness. `forces` unchanged when `adhesion` is empty. Throws InputError
  // ("adhesion", "needs the attraction's range ℓ > 0 (forces.attraction_range)").
  Forces WithAdhesion(Forces forces) const;
  nlohmann::json ToJson() const;

 private:
  void ValidateAdhesion() const;
};

// The state of one agent (index order = the engine's particle order).
struct Agent {
  std::int64_t id = 0;
  int type = 0;
  int generation = 0;  // divisions since the initial agent of its lineage
  int divisions = 0;   // divisions of this agent (it keeps its id; see ChildId)
  double radius = 0.5;
  double age = 0.0;              // time since its last division or the start
  Vec3 polarity{1.0, 0.0, 0.0};  // unit (first k components)
  std::int64_t mother = -1;      // the id of the agent it divided from; −1 for an initial agent
};

// The id of the daughter born at a mother's `count`-th division: a pure function in [0, 2^62).
std::int64_t ChildId(std::int64_t mother_id, int count);

// The segregation index of a mixture of types: the mean, over the agents that touch at least
// one other, of the fraction of the agents touching agent i that share its type,
//   S = (1 / |A|) Σ_{i ∈ A} #{j ~ i : type_j = type_i} / #{j ~ i},   A = {i : #{j ~ i} > 0};
// 0 when no agent touches another. Its expectation for a random mixture of large N with type
// fractions φ_a is Σ_a φ_a² (0.5 for two types half and half); 1 when every contact joins agents of
// one type (fully sorted). types: per agent its type; contacts: the touching pairs (i, j), agent
// indices (Engine::Contacts). Summed in agent order: the same bits for the same input.
double SegregationIndex(std::span<const int> types, std::span<const std::pair<int, int>> contacts);

// The observables at one time.
struct PopulationObservables {
  std::int64_t step = 0;
  double time = 0.0;
  std::vector<std::int64_t> count_per_type;
  std::int64_t count = 0;
  double mean_radius = 0.0;
  std::int64_t contacts = 0;    // pairs with ‖X_i − X_j‖ ≤ contact_factor (r_i + r_j)
  double overlap_before = 0.0;  // largest pair overlap right after the last rule step's
                                // population change, before any projection (pressure proxy)
  double overlap = 0.0;         // largest pair overlap now
  double colony_radius = 0.0;   // max_i ‖X_i − X̄‖ + r_i, X̄ the centroid
  double segregation = 0.0;     // SegregationIndex of the touching pairs
  std::int64_t births = 0;      // so far
  std::int64_t deaths = 0;      // so far (rate)
  std::int64_t removals = 0;    // so far (exit)
};

struct PopulationSummary {
  EngineSummary engine;
  PopulationRules settings;
  Termination termination = Termination::kCompleted;
  std::string message;  // why it stopped early (extinct, count cap, numerical failure)
  std::int64_t rule_steps = 0;
  std::int64_t births = 0, deaths = 0, removals = 0;
  std::int64_t relax_sweeps = 0;
  std::int64_t final_count = 0;
  double max_overlap_before = 0.0;  // max over rule steps of overlap_before
  double rules_seconds = 0.0;       // the rules and the repopulation
  double total_seconds = 0.0;
  bool ok() const { return IsSuccess(termination); }
  // SummaryJson, the counters, "engine" (EngineSummary::ToJson) and "settings".
  nlohmann::json ToJson() const;
};

class Population;
struct PopulationState;  // checkpoint.h
// Called at step 0 and after every rule step; returns false to stop the run (kInterrupted).
using PopulationObserver = std::function<bool(const Population& population)>;

// What user code sees: the whole population at one time, index order (the engine's particle
// order), so that it works on arrays, never agent by agent. Every array of the view, the
// velocities a drift writes and the flags a rule sets are in this one order.
struct PopulationView {
  int dimension = 2;
  std::int64_t step = 0;  // engine steps taken
  double time = 0.0;
  double rule_dt = 0.0;  // Δt = interval · h, the time between rule steps
  // N agents. A rule may change radius (> 0), type (an index of the rules' types) and polarity;
  // id, generation, divisions, age and mother are the population's and must stay.
  std::span<Agent> agents;
  std::vector<std::span<double>> variables;  // per declared variable, N values
  // k·N, wrapped into the periodic domain (Population::CurrentPositions): gathered from the
  // engine at the first call for this state, so user code that reads none pays nothing.
  std::span<const double> positions() const;
  Population* population = nullptr;  // the population viewed (Population::View sets it)
};

// A user drift: called before every engine step; writes velocities (k·N, zero on entry) that
// are added to the agents' drift for that step (a chemotaxis, a push, a flow). It must not
// change the agents. Its cost besides its own work: one pass (Engine::TakeActiveVelocities) that
// checks the velocities, adds the motility, hands them to the engine in its storage order and
// zeroes them for the next call (about 7 % of a 2-D engine step's instructions), and the
// positions only when it reads them.
using UserDrift = std::function<void(const PopulationView& view, std::span<double> velocity)>;

// A user rule: called at every rule step before the built-in rules (growth, death, polarity,
// division), after the engine step. It may change radii, types, polarities and variables through
// the view, and mark agents (N flags each, zero on entry): divide (divides now, whatever the
// type's division rules say) or die (dies now, counted as a death). When it throws, the rule step
// is left pending: the next Step calls it again at the same step count before any engine step
// (so an interrupted run resumes where it stopped, never skipping a rule step).
using UserRule = std::function<void(PopulationView& view, std::span<std::uint8_t> divide,
                                    std::span<std::uint8_t> die)>;

class Population {
 public:
  // geometry: dimension, walls, obstacles, periodic domain (its radius/mobility/stable_ids are
  // replaced by the agents'); types: the initial agents' type indices; positions: k·N0.
  // Throws InputError for bad rules, a type index out of range, or what the engine throws.
  Population(ParticleModel geometry, Forces forces, EngineOptions options, PopulationRules rules,
             std::span<const int> types, std::span<const double> positions);

  // One engine step, then the rules when the step count is a multiple of the interval (first
  // the rule step a throwing user rule left pending, UserRule). Returns false (state kept) when
  // the engine failed, the population is extinct, or the cap is reached. Exceptions of user code
  // reach the caller.
  bool Step();
  // Runs T/h steps (as Engine::Run), calling the observer at step 0 and after each rule step.
  PopulationSummary Run(double T, const PopulationObserver& observer = {});
  // Like Run, from the current step up to step T/h, calling the observer after each rule step
  // only (a resumed run: the current state was observed before the checkpoint).
  PopulationSummary Continue(double T, const PopulationObserver& observer = {});

  // Checkpoints (checkpoint.h): the state between two steps, and its restore on a population
  // made with the same geometry, forces, options and rules (any thread count), after which the
  // steps give the same bits as the population that saved it. RestoreState throws InputError
  // "checkpoint: …" when the state does not fit (types, sizes, ids, the engine's state).
  PopulationState SaveState() const;
  void RestoreState(const PopulationState& state);

  const std::vector<Agent>& agents() const { return agents_; }
  // k·N, index order (empty when no agent is left).
  std::vector<double> Positions() const {
    return agents_.empty() ? std::vector<double>{} : engine_.Positions();
  }
  // The user variable `index` of every agent (index order); declared in rules().variables.
  std::span<const double> variable(std::size_t index) const { return variables_.at(index); }
  // The index of the variable called `name`; InputError "unknown variable 'x' (variables: …)".
  std::size_t VariableIndex(std::string_view name) const;
  const PopulationRules& rules() const { return rules_; }

  // User code (UserDrift, UserRule); an empty function removes it. The run's guarantees hold
  // with it: no overlap beyond the engine's tolerance, and the same bits for any thread count
  // when the user code is deterministic. A rule that leaves a radius ≤ 0 or not finite, or a
  // type out of range, stops the step with InputError naming the agent.
  void SetDrift(UserDrift drift) { drift_ = std::move(drift); }
  void SetRule(UserRule rule) { rule_ = std::move(rule); }
  // The user code set (empty when none).
  const UserDrift& drift() const { return drift_; }
  const UserRule& rule() const { return rule_; }
  // The view user code gets, over this population's own storage (valid until the next step).
  PopulationView View();
  // The positions now (k·N, index order, wrapped; empty when no agent is left), gathered from
  // the engine once per state: later calls before the next step return the same storage.
  std::span<const double> CurrentPositions();
  // Its agents and a user variable alone (no copy of the positions), for bindings' views.
  std::span<Agent> MutableAgents() { return agents_; }
  std::span<double> MutableVariable(std::size_t index) { return variables_.at(index); }
  const Engine& engine() const { return engine_; }

  // Diffusing fields (population_fields.h): the population takes `fields` and couples its agents
  // to them at every rule step (deposit, field steps, samples; proliferation, necrosis and
  // chemotaxis by the samples), and samples them now. Call before the first step; a grid of
  // another dimension, or options that do not fit the rules, throw InputError.
  void CoupleFields(fields::FieldSet fields, FieldCouplingOptions options);
  // The fields (nullptr without), read and write between steps.
  const fields::FieldSet* fields() const { return fields_ ? &*fields_ : nullptr; }
  fields::FieldSet* MutableFields() { return fields_ ? &*fields_ : nullptr; }
  const FieldCouplingOptions& field_coupling() const { return coupling_; }
  // Substrate s sampled at every agent (index order) at the last rule step, or at the coupling:
  // c (N values) and ∇c (k·N). Empty without fields.
  std::span<const double> FieldSamples(int s) const;
  std::span<const double> FieldGradients(int s) const;

  int count() const { return static_cast<int>(agents_.size()); }
  // The observables now (one pass over the candidate pairs for the contacts).
  PopulationObservables Observe() const;
  PopulationSummary summary() const;
  // The ids of the agents that died (death rate or user rule) and of those removed (exit) at the
  // last rule step, in index order; empty before the first.
  const std::vector<std::int64_t>& last_deaths() const { return last_deaths_; }
  const std::vector<std::int64_t>& last_removals() const { return last_removals_; }

 private:
  static ParticleModel ModelOf(const ParticleModel& geometry, const PopulationRules& rules,
                               const std::vector<Agent>& agents);
  std::vector<double> ActiveVelocities() const;
  void ApplyRules();
  std::vector<double> MeanNeighbourPolarity() const;
  void UpdatePolarity(std::size_t i, std::span<const double> x, std::span<const double> mean,
                      Agent* agent) const;
  bool Leaves(const Agent& a, const double* xi, std::int64_t step);
  void Depart(std::int64_t id, bool removed);
  void Divide(Agent a, const double* xi, std::int64_t step, std::vector<Agent>* next,
              std::vector<double>* y);
  void Stop(Termination termination, std::string message);
  bool Divides(const Agent& a, const AgentType& type, std::int64_t step, double dt) const;
  void StepOnce();
  void ApplyDrift();
  void ApplyUserRule(std::vector<std::uint8_t>* divide, std::vector<std::uint8_t>* die);
  void Inherit(std::size_t mother, bool divides, std::vector<std::vector<double>>* next) const;
  PopulationSummary RunTo(std::int64_t last_step, const PopulationObserver& observer);
  void AfterRepopulate();
  // Fields (population_coupling.cpp): deposit, steps and samples before the rules; the samples
  // at the current positions; the necrosis and proliferation rules of agent i (true: it dies).
  void StepFields(std::span<const double> x, double dt);
  void SampleFields();
  bool FieldFate(std::size_t i, Agent* a, bool* starved) const;
  bool HasChemotaxis() const;
  void RestoreFields(const PopulationState& s);
  void AddFieldDrift(std::vector<double>* velocity) const;

  ParticleModel geometry_;
  PopulationRules rules_;
  std::vector<Agent> agents_;                   // before engine_: the engine is built from them
  std::vector<std::vector<double>> variables_;  // per declared variable, N values
  UserDrift drift_;
  UserRule rule_;
  std::vector<double> motility_;  // k·N: v0 p_i since the last rule step, or empty
  std::vector<double> view_positions_, velocity_;
  bool positions_current_ = false;  // view_positions_ hold the engine's positions now
  bool velocity_zero_ = false;      // velocity_ is all zero (the engine took the last drift's)
  bool drifting_ = false;           // the engine's active velocities include the user drift
  bool rules_pending_ = false;      // the user rule threw: the rule step is still to do
  Engine engine_;
  std::unordered_set<std::int64_t> ids_;  // the ids in use (the collision check)
  std::vector<double> last_positions_;    // at the last rule step (velocity alignment)
  PopulationSummary summary_;
  double overlap_before_ = 0.0;
  bool stopped_ = false;
  std::vector<std::int64_t> last_deaths_, last_removals_;
  std::optional<fields::FieldSet> fields_;
  FieldCouplingOptions coupling_;
  std::vector<int> response_index_;  // [type · substrates + substrate]: coupling_.responses, or -1
  std::vector<std::vector<double>> field_samples_, field_gradients_;  // per substrate
  bool samples_current_ = false;  // the samples are those of the current roster
};

inline std::span<const double> PopulationView::positions() const {
  return population->CurrentPositions();
}

}  // namespace moreau::particles
