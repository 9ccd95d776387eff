// The engine as an orchestrator over its parts: it owns the step context they share (the particle
// store, the cell list and colouring, the neighbour list: step_context.h) and the parts with
// buffers of their own (the prediction, the projection sweep, the overlap monitor), and times
// their stages (stage_profile.h). Setup, step, redo, repopulation, relaxation and the run loop.
#include "moreau/particles/engine.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "particles/engine_impl.h"

namespace moreau::particles {

namespace {

using internal::Stage;

// The smallest radius (0 for an empty population: every particle may have left).
double MinRadius(const ParticleModel& model) {
  return model.radius.empty() ? 0.0 : *std::min_element(model.radius.begin(), model.radius.end());
}

// Throws InputError "WHAT: NAME have S entries for N particles in kD" unless size = k·N.
void CheckEntries(std::string_view what, std::string_view name, std::size_t size, int k, int n) {
  if (size != static_cast<std::size_t>(k) * static_cast<std::size_t>(n)) {
    throw InputError(
        fmt::format("{}: {} have {} entries for {} particles in {}D", what, name, size, n, k));
  }
}

// Throws InputError "WHAT: positions must be finite" for a non-finite entry.
void CheckFinite(std::string_view what, std::span<const double> positions) {
  if (!std::all_of(positions.begin(), positions.end(), [](double v) { return std::isfinite(v); })) {
    throw InputError(fmt::format("{}: positions must be finite", what));
  }
}

}  // namespace

void Engine::Impl::Setup(std::span<const double> positions) {
  internal::StepContext& c = context;
  c.options.Validate();
  if (c.model.dimension != 2 && c.model.dimension != 3) {
    throw InputError(fmt::format("dimension must be 2 or 3 for the particle engine (got {})",
                                 c.model.dimension));
  }
  CheckParticleMemory(c.model.dimension, c.model.count(), c.options.memory_limit_bytes);
  c.model.Validate();
  forces.Validate();
  CheckAdhesionClasses(c.model, forces);
  c.k = c.model.dimension;
  CheckEntries("initial state", "positions", positions.size(), c.k, c.model.count());
  if (c.options.check_initial_state) {
    CheckInitialState(c.model, positions, c.options.initial_tolerance);
  } else {
    CheckFinite("initial state", positions);
  }
  c.lexicographic = c.options.order == SweepOrder::kLexicographic;
  c.box = internal::PeriodicBox::Of(c.model);
  ConfigureFor(positions, {});
}

void Engine::Impl::ConfigureFor(std::span<const double> positions, std::span<const double> active) {
  internal::StepContext& c = context;
  const ParticleModel& model = c.model;
  c.n = model.count();
  // Automatic: one thread per ~20000 particles (barriers dominate below), at most the OpenMP
  // default. A number asked for is capped to the processors (more only wait for each other, and
  // tens of thousands of OpenMP threads cannot be created). The results do not depend on it.
  c.threads = c.lexicographic ? 1
              : c.options.threads > 0
                  ? std::min(c.options.threads, std::max(1, omp_get_num_procs()))
                  : std::clamp(c.n / 20000, 1, std::max(1, omp_get_max_threads()));
  c.rmax = model.max_radius();
  c.attraction_range = PairListWidening(forces, MinRadius(model));
  ConfigureSkin();
  const bool uniform_radius = std::all_of(model.radius.begin(), model.radius.end(),
                                          [&](double r) { return r == model.radius.front(); });
  const bool uniform_mobility =
      model.mobility.empty() ||
      std::all_of(model.mobility.begin(), model.mobility.end(), [](double m) { return m == 1.0; });
  c.list.AssumeUniformRadius(uniform_radius && c.n > 0 ? model.radius.front() : 0.0);
  c.store.emplace(model, positions, active);
  prediction.emplace(forces, c.box, c.n, c.options.h, c.options.seed, uniform_mobility);
  sweep.emplace(model, uniform_radius);
  Rebuild(&c.store->current, step);
}

// Minimum images must be unique within the list reach: 2 r_max + ℓ + skin < L/2 on periodic axes.
void Engine::Impl::ConfigureSkin() {
  internal::StepContext& c = context;
  double skin_limit = std::numeric_limits<double>::infinity();
  for (int a = 0; a < c.k; ++a) {
    if (!c.box.periodic[a]) continue;
    const double room = 0.5 * c.box.len[a] - 2.0 * c.rmax - c.attraction_range;
    if (!(room > 0.0)) {
      throw InputError(
          fmt::format("forces.attraction.range {} is too large for periodic axis {} of length {}",
                      c.attraction_range, a, c.box.len[a]));
    }
    skin_limit = std::min(skin_limit, 0.99 * room);
  }
  c.list.Configure(c.box, c.n, c.options.skin_factor * c.rmax, skin_limit, c.attraction_range);
}

// A neighbour-list build at *at (the current or predicted positions): wrap, fit the cell list
// (colouring its blocks when the geometry changed), sort into cells, reorder the storage along
// the cells (coloured order), build the list.
void Engine::Impl::Rebuild(std::vector<double>* at, std::int64_t at_step) {
  const auto timer = profile.Time(Stage::kListBuild);
  internal::StepContext& c = context;
  c.box.WrapAll(at->data(), c.n);
  const double reach = 2.0 * c.rmax + c.attraction_range + c.list.skin();
  if (c.cells.FitAndSort(at->data(), c.store->id.data(), c.n, c.box, reach, c.options.block_cells,
                         c.threads)) {
    c.colouring.Assign(c.cells);
  }
  if (!c.lexicographic) {
    MOREAU_ASSERT(!current_stale);
    current_stale = at == &c.store->predicted;
    // The gather also writes the list's build positions (no copy of them in list.Build).
    c.store->Reorder(c.cells.permutation(), c.threads, !current_stale, at,
                     c.list.BuildPositionsTarget());
    prediction->Reorder(c.cells.permutation(), c.threads);
  }
  c.list.Build(c, at->data(), at_step);
  stats.neighbour_list_builds = c.list.stats().builds;
  stats.candidate_pairs = c.list.stats().candidate_pairs;
  stats.shortest_rebuild_interval = c.list.stats().shortest_rebuild_interval;
}

void Engine::Impl::FreshCurrent() {
  if (!current_stale) return;
  context.store->GatherCurrent(context.cells.permutation(), context.threads);
  current_stale = false;
}

void Engine::Impl::Fail(std::int64_t bad) {
  termination = Termination::kNonFinite;
  failed_step = step + 1;
  failed_particle = bad;
  message = fmt::format(
      "step {} (t = {:.6g}): the drift or noise gave a non-finite position for particle {}; "
      "the state of step {} is kept",
      step + 1, static_cast<double>(step + 1) * context.options.h, bad, step);
}

// The sweeps of one step, redone from the step's start with a fresh list (and a wider skin if
// that was fresh already) while the no-missed-contact bound is reached. moved: the bound on the
// distance of the predicted positions from the build positions. relax: the sweeps start from the
// current positions (Relax) instead of a prediction.
void Engine::Impl::SweepUntilAccepted(double moved, int sweeps, bool relax) {
  internal::StepContext& c = context;
  for (int attempt = 0;; ++attempt) {
    std::int64_t proj = 0;
    // The sum over sweeps of the longest path bounds every particle's path in this step.
    double max_path = 0.0;
    {
      const auto timer = profile.Time(Stage::kSweep);
      for (int s = 0; s < sweeps; ++s) {
        const bool monitored = s == sweeps - 1 && !relax && c.options.monitor_overlap;
        max_path += sweep->Sweep(c, &proj, monitored ? monitor.Prepare(c.threads) : nullptr);
      }
    }
    const std::int64_t fixed = static_cast<std::int64_t>(c.n) * sweep->fixed_sets();
    stats.constraint_evaluations += sweeps * (c.list.pairs() + fixed);
    stats.constraint_sets += sweeps * (static_cast<std::int64_t>(c.n) * (c.n - 1) / 2 + fixed);
    stats.projections += proj;
    if (c.list.Accept(moved + max_path)) return;
    if (sweeps == 1 && AcceptEach()) return;
    ++stats.verlet_retries;
    if (attempt >= 20) {
      throw NumericalError(fmt::format(
          "step {}: a particle moves more than the Verlet skin allows in one sweep", step + 1));
    }
    if (!c.list.PrepareRedo()) {
      throw NumericalError(fmt::format(
          "step {}: projections move particles farther than the periodic domain allows the "
          "neighbour lists to reach",
          step + 1));
    }
    Redo(relax);
    moved = 0.0;
  }
}

// A redo's start: the step's prediction again (relaxing: the current positions) and a list
// built there.
void Engine::Impl::Redo(bool relax) {
  internal::StepContext& c = context;
  {
    const auto timer = profile.Time(Stage::kPrediction);
    FreshCurrent();
    if (relax) {
      c.store->predicted = c.store->current;
    } else {
      prediction->Predict(c, step);  // the same finite values as the step's first prediction
    }
  }
  Rebuild(&c.store->predicted, step + 1);
}

// The list's per-particle acceptance (NeighbourList::AcceptEach) with the last sweep's paths.
bool Engine::Impl::AcceptEach() {
  const internal::StepContext& c = context;
  sweep->StartPositions(c.store->predicted.data(), &sweep_start);
  path_scratch.resize(static_cast<std::size_t>(c.n));
  for (int s = 0; s < c.n; ++s) path_scratch[static_cast<std::size_t>(s)] = sweep->PathOf(s);
  return context.list.AcceptEach(sweep_start.data(), c.store->predicted.data(),
                                 c.store->radius.data(), path_scratch, c.cells, c.members(),
                                 c.threads);
}

// predict → (build if the skin bound says so) → sweeps (redone if needed) → accept → monitor.
bool Engine::Impl::Step() {
  if (termination != Termination::kCompleted) return false;
  const auto total = profile.Time(Stage::kTotal);
  const FreshCurrentOnExit fresh{this};
  internal::StepContext& c = context;
  internal::PredictionOutcome predicted;
  // The list's exact bound rides along with the prediction when the last step's move says it
  // will be needed (saving a pass over the positions).
  std::optional<internal::ExactBound> fused;
  {
    const auto timer = profile.Time(Stage::kPrediction);
    if (prediction->attracts()) prediction->Attraction(c);
    if (prediction->measures_density()) prediction->LocalDensity(c);
    if (prediction->walks_collision_free()) prediction->CollisionFreeWalk(c);
    if (c.list.ExactBoundLikely(last_step_move)) fused = c.list.ExactBoundRequest();
    predicted = prediction->Predict(c, step, fused ? &*fused : nullptr);
  }
  max_coordinate = predicted.max_coordinate;
  last_step_move = predicted.max_move;
  if (predicted.bad_id >= 0) {
    Fail(predicted.bad_id);
    return false;
  }
  c.list.MarkPredicted();
  double moved = c.list.BoundAfterPrediction(predicted.max_move, c.store->predicted.data(),
                                             c.threads, fused ? &*fused : nullptr);
  if (c.list.NeedsBuild(moved, c.options.sweeps == 1)) {
    c.list.RelaxSkin();
    Rebuild(&c.store->predicted, step + 1);
    moved = 0.0;
  }
  SweepUntilAccepted(moved, c.options.sweeps, false);
  c.store->current.swap(c.store->predicted);
  current_stale = false;  // the old current positions are scratch now
  ++step;
  stats.steps = step;
  stats.time = static_cast<double>(step) * c.options.h;
  if (c.options.monitor_overlap) Monitor();
  return true;
}

// The largest pair overlap after a step (OverlapMonitor), exact.
void Engine::Impl::Monitor() {
  const auto timer = profile.Time(Stage::kMonitor);
  stats.last_overlap = monitor.Measure(context, max_coordinate);
  stats.max_overlap = std::max(stats.max_overlap, stats.last_overlap);
}

// A new particle set between steps: the parts are set up again for it (the step count, the
// counters and the nominal skin's rules carry on) and the list is built at the new positions.
void Engine::Impl::Repopulate(std::span<const double> positions, std::span<const double> active) {
  const auto total = profile.Time(Stage::kTotal);
  const internal::StepContext& c = context;
  if (c.model.dimension != c.k) {
    throw InputError(
        fmt::format("repopulate: the dimension must stay {} (got {})", c.k, c.model.dimension));
  }
  c.model.Validate();
  CheckAdhesionClasses(c.model, forces);
  CheckParticleMemory(c.k, c.model.count(), c.options.memory_limit_bytes);
  CheckEntries("repopulate", "positions", positions.size(), c.k, c.model.count());
  if (!active.empty()) {
    CheckEntries("repopulate", "active velocities", active.size(), c.k, c.model.count());
  }
  CheckFinite("repopulate", positions);
  ConfigureFor(positions, active);
}

// Sweeps at fixed positions (no drift, no noise) until every pair overlap is ≤ tolerance.
int Engine::Impl::Relax(double tolerance, int max_sweeps) {
  const auto total = profile.Time(Stage::kTotal);
  const FreshCurrentOnExit fresh{this};
  internal::StepContext& c = context;
  int done = 0;
  while (done < max_sweeps && MaxOverlap() > tolerance) {
    c.store->predicted = c.store->current;
    c.list.MarkPredicted();
    double moved = c.list.BoundAfterPrediction(0.0, c.store->predicted.data(), c.threads);
    if (c.list.NeedsBuild(moved, true)) {
      c.list.RelaxSkin();
      Rebuild(&c.store->predicted, step);
      moved = 0.0;
    }
    SweepUntilAccepted(moved, 1, true);
    c.store->current.swap(c.store->predicted);
    current_stale = false;
    ++done;
  }
  return done;
}

// ---------------------------------------------------------------------------------------------
// Engine.

Engine::Engine(ParticleModel model, Forces forces, EngineOptions options,
               std::span<const double> positions)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  {
    const auto timer = m.profile.Time(Stage::kSetup);
    m.context.model = std::move(model);
    m.forces = std::move(forces);
    m.context.options = options;
    m.Setup(positions);
  }
  m.profile.Clear(Stage::kListBuild);  // the first build is part of the setup
}

Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

bool Engine::Step() { return impl_->Step(); }

void Engine::Repopulate(ParticleModel model, std::span<const double> positions,
                        std::span<const double> active_velocity) {
  impl_->context.model = std::move(model);
  impl_->Repopulate(positions, active_velocity);
}

void Engine::SetActiveVelocities(std::span<const double> active_velocity) {
  internal::StepContext& c = impl_->context;
  internal::ParticleStore& store = *c.store;
  if (active_velocity.empty()) {
    store.active.clear();
    return;
  }
  CheckEntries("active velocities", "velocities", active_velocity.size(), c.k, c.n);
  const auto k = static_cast<std::size_t>(c.k);
  store.active.resize(k * static_cast<std::size_t>(c.n));
  for (std::size_t s = 0; s < store.id.size(); ++s) {
    const double* from = active_velocity.data() + k * static_cast<std::size_t>(store.id[s]);
    std::copy(from, from + k, store.active.data() + k * s);
  }
}

int Engine::TakeActiveVelocities(std::span<double> velocity, std::span<const double> added) {
  internal::StepContext& c = impl_->context;
  CheckEntries("active velocities", "velocities", velocity.size(), c.k, c.n);
  if (!added.empty()) CheckEntries("active velocities", "added velocities", added.size(), c.k, c.n);
  return c.store->TakeActive(velocity, added, c.threads);
}

int Engine::Relax(double tolerance, int max_sweeps) {
  if (!(tolerance >= 0.0)) {
    throw InputError(fmt::format("relax tolerance must be ≥ 0 (got {})", tolerance));
  }
  return impl_->Relax(tolerance, max_sweeps);
}

EngineSummary Engine::Run(double T, const EngineObserver& observer) {
  const std::int64_t steps = StepCount(T, impl_->context.options.h);
  if (observer && !observer(*this)) return Interrupted();
  return RunTo(impl_->step + steps, observer);
}

EngineSummary Engine::Continue(double T, const EngineObserver& observer) {
  return RunTo(StepCount(T, impl_->context.options.h), observer);
}

EngineSummary Engine::RunTo(std::int64_t last_step, const EngineObserver& observer) {
  while (impl_->step < last_step) {
    try {
      if (!Step()) break;
    } catch (const NumericalError& e) {  // the state is the last good one
      Impl& m = *impl_;
      m.termination = Termination::kNonFinite;
      m.failed_step = m.step + 1;
      m.message = fmt::format("{}; the state of step {} is kept", e.what(), m.step);
      break;
    }
    if (observer && !observer(*this)) return Interrupted();
  }
  return summary();
}

EngineSummary Engine::Interrupted() const {
  EngineSummary s = summary();
  s.termination = Termination::kInterrupted;
  s.message = "stopped by the observer";
  return s;
}

}  // namespace moreau::particles
