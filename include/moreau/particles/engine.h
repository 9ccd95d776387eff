// The particle engine: first-order PBD for N ~ 10^4 … 10^6 overdamped particles with volume
// exclusion, neighbour lists, noise and a deterministic OpenMP sweep.
//
// One step (h > 0, k = dimension):
//   1. drift u_i at the current positions X (forces.h), noise ξ_i(seed, id, step);
//   2. predicted positions Y_i = X_i + h u_i + √(2 D h) ξ_i;
//   3. one PBD sweep over all sets at Y: every candidate pair (non-overlap), then for every
//      particle its walls (in model order), sphere obstacles, segment obstacles;
//   4. positions wrapped into [lo, hi) on periodic axes (reported positions; the engine keeps an
//      unwrapped copy between neighbour-list builds).
//
// Sweep order (SweepOrder):
//   kLexicographic  pairs (i, j), i < j by particle id, lexicographic, single thread: the order of
//                   moreau::pbd::ParticleConstraints, so on its models (walls only) the engine
//                   gives its results to round-off (bit-identical for the harmonic trap).
//   kColoured       space is cut into blocks of block_cells^k grid cells (cell edge ≥ the
//                   neighbour-list reach), blocks are coloured by (b_a mod 3) over the axes (3^k
//                   colours), so two blocks of one colour have disjoint 3^k neighbourhoods. The
//                   sweep visits the colours in order, within a colour the blocks in Morton order,
//                   within a block its particles in storage order (cells row-major, then id) and
//                   each particle's pairs with later particles in a fixed cell-offset order. Blocks
//                   of one colour touch disjoint particles and run in parallel, so the result is
//                   bit-for-bit the same for any thread count. The order depends only on the
//                   positions at the last neighbour-list build and the ids.
//
// Neighbour lists: a uniform cell grid (edge ≥ reach = 2 max r + attraction range + skin) filled
// by counting sort, Verlet half-lists of the pairs closer than r_i + r_j + ℓ + skin, and the
// particle storage reordered along the blocks' Morton curve at every build (ids are kept).
// A build happens when some predicted position has moved more than skin/4 from the last build
// (with one sweep per step: more than max(64, N/16) of them, or one by skin/2).
// No missed contacts, exactly: during a sweep each particle's distance from its build position
// is bounded by its predicted displacement plus the length of the projection moves applied to it
// so far; if after a sweep that bound reached skin/2 for some particle — and, with one sweep per
// step, the per-particle test also fails (every bound below the skin, at most max(64, N/16)
// particles beyond skin/2, none of them able to meet an unlisted particle within 2 cells; the
// path bound per particle is (‖Y_i − X_i^build‖ + ‖X_i' − X_i^build‖ + path_i)/2) — the step is
// redone from its start with a fresh list (and, if that was fresh already, a doubled skin, which
// relaxes back by halves toward the nominal skin at later regular builds) — a pair left out of the
// list is then provably farther apart than r_i + r_j + ℓ throughout the sweep, so its projection is
// the identity and leaving it out changes no bit. Such redos are counted (verlet_retries).
//
// Bad input throws InputError (message names the field); a non-finite predicted position stops
// the step, keeps the last good state and reports the step and particle id (Step returns false;
// Run's summary has termination kNonFinite; Run also reports Step's NumericalError so).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/enum_names.h"
#include "moreau/common/field_list.h"
#include "moreau/common/termination.h"
#include "moreau/particles/forces.h"
#include "moreau/particles/initial_state.h"  // CheckInitialState, RandomSequentialAddition
#include "moreau/particles/model.h"

namespace moreau::particles {

enum class SweepOrder { kColoured, kLexicographic };
inline constexpr EnumNames<SweepOrder, 2> kSweepOrderNames{
    {{SweepOrder::kColoured, "coloured"}, {SweepOrder::kLexicographic, "lexicographic"}}};
// "coloured", "lexicographic"; Parse throws InputError for other names.
std::string_view SweepOrderName(SweepOrder order);
SweepOrder ParseSweepOrder(std::string_view name);

enum class NeighbourSearch {
  kCellGrid,    // cell grid + Verlet lists: O(N) per build
  kBruteForce,  // all pairs within reach by an O(N²) loop; opt-in, for tests of the grid
};
inline constexpr EnumNames<NeighbourSearch, 2> kNeighbourSearchNames{
    {{NeighbourSearch::kCellGrid, "cell_grid"}, {NeighbourSearch::kBruteForce, "brute_force"}}};

struct EngineOptions {
  double h = 1e-3;         // time step, > 0
  std::uint64_t seed = 1;  // noise key
  SweepOrder order = SweepOrder::kColoured;
  NeighbourSearch search = NeighbourSearch::kCellGrid;
  double skin_factor = 1.0;     // Verlet skin = skin_factor · max r, > 0
  int threads = 0;              // OpenMP threads; 0: max(1, min(omp_get_max_threads(),
                                // N / 20000)); more than omp_get_num_procs() are capped to it.
                                // Results do not depend on it. kLexicographic
                                // always runs on one thread.
  int block_cells = 0;          // colouring block edge in cells, ≥ 1; 0: automatic from the
                                // cell count (⌊√(cells/72)⌋ in 2D clamped to [2, 64],
                                // ⌊∛(cells/216)⌋ in 3D clamped to [2, 16]: ≥ 8 blocks per
                                // colour). Part of the definition of the coloured sweep order.
  int sweeps = 1;               // PBD sweeps per step, ≥ 1. 1 is the paper's PBD (eq. 4);
                                // s > 1 repeats the sweep s times (PNGS truncated at s sweeps),
                                // which shrinks the overlaps of deep contact chains (crowds
                                // pressing on a door) at s times the sweep cost.
  bool monitor_overlap = true;  // track the max pair overlap after every step, exactly: over
                                // the rows the step's last sweep found near contact, or a pass
                                // over all candidate pairs when those might not hold them all
  bool check_initial_state = true;  // CheckInitialState(model, positions, initial_tolerance)
  double initial_tolerance = 1e-9;
  std::int64_t memory_limit_bytes = 0;  // for CheckParticleMemory; 0: AvailableMemory()

  static const FieldList<EngineOptions>& Fields();  // key, range, help of every field
  // Throws InputError(key, reason) ("h", "must be > 0 (got 0)"), …).
  void Validate() const;
  // Every field by its key ("order": "coloured", "search": "cell_grid" | "brute_force").
  nlohmann::json ToJson() const;
};

// Counters and timings; every count is exact and independent of the thread count.
struct EngineStats {
  std::int64_t steps = 0;
  double time = 0.0;                            // steps · h
  std::int64_t neighbour_list_builds = 0;       // Verlet-list builds (the initial one included)
  std::int64_t verlet_retries = 0;              // steps redone because the skin bound was reached
  std::int64_t shortest_rebuild_interval = -1;  // fewest steps between two list builds (a redo's
                                                // build counts at its step); −1: one build
  std::int64_t candidate_pairs = 0;             // pairs in the list at the last build
  std::int64_t constraint_evaluations = 0;      // sets visited: candidate pairs + N · (walls +
                                                // obstacles), per sweep
  std::int64_t constraint_sets = 0;             // the paper's count m per sweep, summed: N(N−1)/2
                                                // pairs + N · (walls + obstacles)
  std::int64_t projections = 0;                 // projections that moved a particle
  double max_overlap = 0.0;                     // max over monitored steps of the largest pair
                             // overlap max(0, r_i + r_j − ‖X_i − X_j‖) (exact)
  double last_overlap = 0.0;  // the same after the last monitored step
  // Wall-clock seconds per phase.
  double setup_seconds = 0.0;      // validation, allocation, first build
  double force_seconds = 0.0;      // drift, noise and prediction
  double neighbour_seconds = 0.0;  // list builds and reordering
  double sweep_seconds = 0.0;      // PBD sweeps
  double monitor_seconds = 0.0;    // overlap monitor
  double total_seconds = 0.0;      // all steps (setup excluded)
};

struct EngineSummary {
  EngineStats stats;
  EngineOptions settings;                             // the options the engine ran with
  Termination termination = Termination::kCompleted;  // kCompleted or kNonFinite
  std::string message;                                // why it stopped, naming step and particle
  std::int64_t failed_step = -1;                      // the step that failed (1-based)
  std::int64_t failed_particle = -1;  // its particle id (−1 when the failure names none)
  bool ok() const { return IsSuccess(termination); }
  std::string BriefReport() const;  // one line
  // SummaryJson (termination, ok, message, total_seconds), the counters and *_seconds of stats
  // under their names here, failed_step/failed_particle on failure, and "settings".
  nlohmann::json ToJson() const;
};

class Engine;
struct EngineState;  // checkpoint.h

// Called with the engine at step 0 (the initial state) and after every step taken; returns
// whether to continue (false stops the run: kInterrupted). It reads what it needs: step(),
// time(), Stored() (no copy) or CopyPositions / Positions (id order, a copy of k·N values), so an
// observer that needs no positions costs nothing per step.
using EngineObserver = std::function<bool(const Engine& engine)>;

// The engine's positions as stored, without a copy: slot s holds particle ids[s] at
// positions[k·s … k·s + k − 1]. The slots are in the engine's storage order (which changes at
// neighbour-list builds) and positions on periodic axes are NOT wrapped into the domain. Valid
// until the next Step.
struct StoredPositions {
  std::span<const int> ids;
  std::span<const double> positions;
};

class Engine {
 public:
  // Validates model, forces and options (InputError), checks the memory estimate before
  // allocating and, unless disabled, the initial state (CheckInitialState). positions: size k·N,
  // particle-id order. Builds the first neighbour list.
  Engine(ParticleModel model, Forces forces, EngineOptions options,
         std::span<const double> positions);
  ~Engine();
  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // One step. Returns false, leaving the state of the last good step, when a predicted position
  // is not finite (summary() names the step and particle); further calls then return false.
  // Throws NumericalError in the pathological case that one sweep moves particles farther than
  // any neighbour list can cover (20 redos in one step, or a skin at the periodic limit).
  bool Step();

  // A changing population (population.h): replaces the particle set between steps. model: the
  // new set (its dimension must stay; its radii, mobilities, stable_ids and fixed sets are
  // used), positions: k·N in its index order, active_velocity: k·N velocities added to the
  // drift u_i (an agent's motility along its polarity), or empty. The step count, time and
  // counters carry on; the neighbour list is rebuilt at the new positions (one build, counted).
  // No initial-state check: overlaps (the daughters of a division) are left to the projections
  // of the next steps or to Relax. Throws InputError for a bad model, sizes or non-finite
  // positions (the engine is then unusable).
  void Repopulate(ParticleModel model, std::span<const double> positions,
                  std::span<const double> active_velocity = {});
  // Replaces the active velocities (k·N, id order; empty: none) from the next step on, without
  // a rebuild. Throws InputError for a wrong size.
  void SetActiveVelocities(std::span<const double> active_velocity);
  // The same for a velocity field that changes every step (user code's drift, population.h):
  // the active velocities become velocity + added (each k·N, id order; added may be empty) in
  // one pass over the particles, which also sets velocity to zero (a buffer ready for the next
  // step's field). Returns −1 when every velocity is finite, else the lowest particle id whose
  // velocity is not (the velocities are set all the same: do not step before replacing them).
  // Throws InputError for a wrong size.
  int TakeActiveVelocities(std::span<double> velocity, std::span<const double> added = {});
  // Projection sweeps at the current positions (no drift, no noise, the step count unchanged)
  // until the largest pair overlap is ≤ tolerance (≥ 0, else InputError) or max_sweeps were
  // done; returns the number of sweeps.
  int Relax(double tolerance, int max_sweeps);

  // Runs n = T/h steps (T/h a whole number to within 1e−9, else InputError), calling the
  // observer, if given, at step 0 and after every step. Stops early at a numerical failure (a
  // non-finite position, or Step's NumericalError) with termination kNonFinite, the message
  // naming the step, and the last good state kept; never throws for it. Stops when the observer
  // returns false, right after the call, with termination kInterrupted and the message "stopped
  // by the observer"; the engine stays usable (Step, Run and Continue go on from its step).
  EngineSummary Run(double T, const EngineObserver& observer = {});
  // Like Run, from the current step up to step T/h, calling the observer after every step only
  // (a resumed run: the current state was observed before the checkpoint).
  EngineSummary Continue(double T, const EngineObserver& observer = {});

  // Checkpoints (checkpoint.h): the state between two steps, and its restore on an engine made
  // with the same model, forces and options (any thread count), after which the steps give the
  // same bits as the engine that saved it. RestoreState throws InputError "checkpoint: …" when
  // the state does not fit the engine (dimension, count, ids, sizes, non-finite values).
  EngineState SaveState() const;
  void RestoreState(const EngineState& state);

  // Positions (size k·N, id order, wrapped into the periodic domain).
  void CopyPositions(std::span<double> out) const;
  std::vector<double> Positions() const;
  // The stored positions without a copy (see StoredPositions).
  StoredPositions Stored() const;

  int dimension() const;
  int count() const;
  std::int64_t step() const;  // steps taken
  double time() const;        // step() · h
  int threads() const;
  const ParticleModel& model() const;
  const Forces& forces() const;
  const EngineOptions& options() const;
  EngineSummary summary() const;

  // The largest pair overlap at the current positions over the candidate pairs (which contain
  // every overlapping pair, so it is the exact maximum over all pairs).
  double MaxPairOverlap() const;
  // The largest violation of any set (pairs, walls, obstacles) at the current positions.
  double MaxViolation() const;
  // The pairs that touch at the current positions: ‖X_i − X_j‖ ≤ factor (r_i + r_j), with the
  // minimum image on periodic axes (a pair touches across a periodic boundary as it does
  // mid-box), as (id_i, id_j), id_i < id_j, sorted; factor in [1, 1.5] (InputError otherwise).
  // The engine's one definition of touching: ContactCounts and the population's rules use it.
  // Exact: one pass over the candidate pairs while they provably hold every touching pair (the
  // list's reach, less twice the distance moved since its build, exceeds (factor − 1) 2 max r),
  // else over the pairs of a search made for the query.
  std::vector<std::pair<int, int>> Contacts(double factor) const;
  // For every particle (id order) the number of particles it touches (Contacts).
  std::vector<int> ContactCounts(double factor) const;
  // The candidate pairs of the current list as (id_i, id_j), id_i < id_j, sorted.
  std::vector<std::pair<int, int>> CandidatePairs() const;

 private:
  EngineSummary RunTo(std::int64_t last_step, const EngineObserver& observer);
  EngineSummary Interrupted() const;  // the summary of a run its observer stopped
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Bytes the engine needs for `count` particles in `dimension` (positions, buffers, neighbour
// lists at a generous contact count, grid): an estimate made before anything is allocated.
std::int64_t EstimateEngineBytes(int dimension, std::int64_t count);

// Throws InputError "N particles need about X, more than the Y available (SOURCE)" when
// EstimateEngineBytes exceeds limit_bytes (0: moreau::AvailableMemory(), which respects
// `ulimit -v` and cgroup limits). Call it before generating a large initial state.
void CheckParticleMemory(int dimension, std::int64_t count, std::int64_t limit_bytes = 0);

struct FixOverlapsOptions {
  double tolerance = 1e-10;  // stop when every violation ≤ tolerance · min r
  int max_sweeps = 100000;   // NumericalError when reached
  SweepOrder order = SweepOrder::kColoured;
  int threads = 0;
};

// Projects an infeasible state to a feasible one: repeated PBD sweeps of all sets (no drift, no
// noise) at fixed positions until the largest violation is ≤ tolerance · min r. Returns the
// number of sweeps (0 if already feasible). positions: size k·N, id order, modified in place.
// Throws InputError for a bad model, NumericalError when max_sweeps is reached.
int FixOverlaps(const ParticleModel& model, std::span<double> positions,
                const FixOverlapsOptions& options = {});

}  // namespace moreau::particles
