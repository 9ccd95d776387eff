// The engine as an orchestrator over its parts (each owning its data): the particle store, the
// cell list (grid and Morton order), the colouring, the neighbour list (skin and bound), the
// prediction and the projection sweep.
#include "moreau/particles/engine.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "particles/engine_impl.h"

namespace moreau::particles {

namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// The smallest radius (0 for an empty population: every particle may have left).
double MinRadius(const ParticleModel& model) {
  return model.radius.empty() ? 0.0 : *std::min_element(model.radius.begin(), model.radius.end());
}
}  // namespace

void Engine::Impl::Setup(std::span<const double> positions) {
  options.Validate();
  if (model.dimension != 2 && model.dimension != 3) {
    throw InputError(
        fmt::format("dimension must be 2 or 3 for the particle engine (got {})", model.dimension));
  }
  CheckParticleMemory(model.dimension, model.count(), options.memory_limit_bytes);
  model.Validate();
  forces.Validate();
  k = model.dimension;
  n = model.count();
  if (positions.size() != static_cast<std::size_t>(k) * static_cast<std::size_t>(n)) {
    throw InputError(fmt::format("initial state: positions have {} entries for {} particles in {}D",
                                 positions.size(), n, k));
  }
  if (options.check_initial_state) {
    CheckInitialState(model, positions, options.initial_tolerance);
  } else {
    for (double v : positions) {
      if (!std::isfinite(v)) throw InputError("initial state: positions must be finite");
    }
  }
  // Automatic: one thread per ~20000 particles (barriers dominate below), at most the OpenMP
  // default. The results do not depend on it.
  threads = options.threads > 0 ? options.threads
                                : std::clamp(n / 20000, 1, std::max(1, omp_get_max_threads()));
  lexicographic = options.order == SweepOrder::kLexicographic;
  if (lexicographic) threads = 1;
  rmax = model.max_radius();
  attraction_range = PairListWidening(forces, MinRadius(model));
  box = internal::PeriodicBox::Of(model);
  ConfigureSkin();
  const bool uniform_radius = std::all_of(model.radius.begin(), model.radius.end(),
                                          [&](double r) { return r == model.radius.front(); });
  const bool uniform_mobility =
      model.mobility.empty() ||
      std::all_of(model.mobility.begin(), model.mobility.end(), [](double m) { return m == 1.0; });
  list.AssumeUniformRadius(uniform_radius && n > 0 ? model.radius.front() : 0.0);
  store.emplace(model, positions);
  prediction.emplace(forces, box, n, options.h, options.seed, uniform_mobility);
  sweep.emplace(model, uniform_radius);
  Rebuild(&store->current, 0);
}

// Minimum images must be unique within the list reach: 2 r_max + ℓ + skin < L/2 on periodic axes.
void Engine::Impl::ConfigureSkin() {
  double skin_limit = std::numeric_limits<double>::infinity();
  for (int a = 0; a < k; ++a) {
    if (!box.periodic[a]) continue;
    const double room = 0.5 * box.len[a] - 2.0 * rmax - attraction_range;
    if (!(room > 0.0)) {
      throw InputError(
          fmt::format("forces.attraction.range {} is too large for periodic axis {} of length {}",
                      attraction_range, a, box.len[a]));
    }
    skin_limit = std::min(skin_limit, 0.99 * room);
  }
  list.Configure(box, n, options.skin_factor * rmax, skin_limit, attraction_range);
}

// A neighbour-list build at *at (the current or predicted positions): wrap, fit the cell list
// (colouring its blocks when the geometry changed), sort into cells, reorder the storage along
// the cells (coloured order), build the list.
void Engine::Impl::Rebuild(std::vector<double>* at, std::int64_t at_step) {
  const auto t0 = Clock::now();
  box.WrapAll(at->data(), n);
  const double reach = 2.0 * rmax + attraction_range + list.skin();
  if (cells.FitAndSort(at->data(), store->id.data(), n, box, reach, options.block_cells, threads)) {
    colouring.Assign(cells);
  }
  const int* members = cells.permutation().data();
  if (!lexicographic) {
    MOREAU_ASSERT(!current_stale);
    current_stale = at == &store->predicted;
    // The gather also writes the list's build positions (no copy of them in list.Build).
    store->Reorder(cells.permutation(), threads, !current_stale, at, list.BuildPositionsTarget());
    prediction->Reorder(cells.permutation(), threads);
    members = nullptr;  // storage is in cell order
  }
  list.Build(at->data(), store->radius.data(), cells, members,
             lexicographic || options.search == NeighbourSearch::kBruteForce,
             options.search == NeighbourSearch::kBruteForce, at_step, threads);
  stats.neighbour_list_builds = list.stats().builds;
  stats.candidate_pairs = list.stats().candidate_pairs;
  stats.shortest_rebuild_interval = list.stats().shortest_rebuild_interval;
  stats.neighbour_seconds += Seconds(t0, Clock::now());
}

void Engine::Impl::Predict(double* max_move, std::int64_t* bad_id, internal::ExactBound* bound) {
  prediction->Predict(store->current.data(), store->predicted.data(), store->id.data(),
                      store->noise_key.empty() ? nullptr : store->noise_key.data(),
                      store->active.empty() ? nullptr : store->active.data(),
                      store->mobility.data(), step, threads, max_move, bad_id, &max_coordinate,
                      bound);
}

void Engine::Impl::FreshCurrent() {
  if (!current_stale) return;
  store->GatherCurrent(cells.permutation(), threads);
  current_stale = false;
}

void Engine::Impl::Fail(std::int64_t bad) {
  termination = Termination::kNonFinite;
  failed_step = step + 1;
  failed_particle = bad;
  message = fmt::format(
      "step {} (t = {:.6g}): the drift or noise gave a non-finite position for particle {}; "
      "the state of step {} is kept",
      step + 1, static_cast<double>(step + 1) * options.h, bad, step);
}

// The sweeps of one step, redone from the step's start with a fresh list (and a wider skin if
// that was fresh already) while the no-missed-contact bound is reached. moved: the bound on the
// distance of the predicted positions from the build positions. relax: the sweeps start from the
// current positions (Relax) instead of a prediction.
void Engine::Impl::SweepUntilAccepted(double moved, int sweeps, bool relax) {
  for (int attempt = 0;; ++attempt) {
    const auto ts = Clock::now();
    std::int64_t proj = 0;
    // The sum over sweeps of the longest path bounds every particle's path in this step.
    double max_path = 0.0;
    for (int s = 0; s < sweeps; ++s) {
      const bool monitored = s == sweeps - 1 && !relax && options.monitor_overlap;
      max_path += sweep->Sweep(store->predicted.data(), store->radius.data(), list, colouring,
                               cells, lexicographic, threads, &proj,
                               monitored ? monitor.Prepare(threads) : nullptr);
    }
    stats.sweep_seconds += Seconds(ts, Clock::now());
    const std::int64_t fixed = static_cast<std::int64_t>(n) * sweep->fixed_sets();
    stats.constraint_evaluations += sweeps * (list.pairs() + fixed);
    stats.constraint_sets += sweeps * (static_cast<std::int64_t>(n) * (n - 1) / 2 + fixed);
    stats.projections += proj;
    if (list.Accept(moved + max_path)) return;
    if (sweeps == 1 && AcceptEach()) return;
    ++stats.verlet_retries;
    if (attempt >= 20) {
      throw NumericalError(fmt::format(
          "step {}: a particle moves more than the Verlet skin allows in one sweep", step + 1));
    }
    if (!list.PrepareRedo()) {
      throw NumericalError(fmt::format(
          "step {}: projections move particles farther than the periodic domain allows the "
          "neighbour lists to reach",
          step + 1));
    }
    const auto tp = Clock::now();
    double unused = 0.0;
    std::int64_t bad = -1;
    FreshCurrent();
    if (relax) {
      store->predicted = store->current;
    } else {
      Predict(&unused, &bad);
    }
    stats.force_seconds += Seconds(tp, Clock::now());
    Rebuild(&store->predicted, step + 1);
    moved = 0.0;
  }
}

// The list's per-particle acceptance (NeighbourList::AcceptEach) with the last sweep's paths.
bool Engine::Impl::AcceptEach() {
  sweep->StartPositions(store->predicted.data(), &sweep_start);
  path_scratch.resize(static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s) path_scratch[static_cast<std::size_t>(s)] = sweep->PathOf(s);
  return list.AcceptEach(sweep_start.data(), store->predicted.data(), store->radius.data(),
                         path_scratch, cells, lexicographic ? cells.permutation().data() : nullptr,
                         threads);
}

// predict → (build if the skin bound says so) → sweeps (redone if needed) → accept.
bool Engine::Impl::Step() {
  if (termination != Termination::kCompleted) return false;
  const auto t0 = Clock::now();
  const FreshCurrentOnExit fresh{this};
  if (prediction->attracts()) {
    prediction->Attraction(store->current.data(), store->radius.data(), list, colouring, cells,
                           lexicographic, threads);
  }
  if (prediction->measures_density()) {
    prediction->LocalDensity(store->current.data(), list, colouring, cells, lexicographic, threads);
  }
  double step_move = 0.0;
  std::int64_t bad = -1;
  // The list's exact bound rides along with the prediction when the last step's move says it
  // will be needed (saving a pass over the positions).
  std::optional<internal::ExactBound> fused;
  if (list.ExactBoundLikely(last_step_move)) fused = list.ExactBoundRequest();
  Predict(&step_move, &bad, fused ? &*fused : nullptr);
  last_step_move = step_move;
  stats.force_seconds += Seconds(t0, Clock::now());
  if (bad >= 0) {
    Fail(bad);
    return false;
  }
  list.MarkPredicted();
  double moved = list.BoundAfterPrediction(step_move, store->predicted.data(), threads,
                                           fused ? &*fused : nullptr);
  if (list.NeedsBuild(moved, options.sweeps == 1)) {
    list.RelaxSkin();
    Rebuild(&store->predicted, step + 1);
    moved = 0.0;
  }
  SweepUntilAccepted(moved, options.sweeps, false);
  store->current.swap(store->predicted);
  current_stale = false;  // the old current positions are scratch now
  ++step;
  stats.steps = step;
  stats.time = static_cast<double>(step) * options.h;
  if (options.monitor_overlap) {
    const auto tm = Clock::now();
    stats.last_overlap = monitor.Measure(list, store->current.data(), store->radius.data(), n,
                                         threads, max_coordinate, rmax);
    stats.max_overlap = std::max(stats.max_overlap, stats.last_overlap);
    stats.monitor_seconds += Seconds(tm, Clock::now());
  }
  stats.total_seconds += Seconds(t0, Clock::now());
  return true;
}

// A new particle set between steps: the parts are set up again for it (the step count, the
// counters and the nominal skin's rules carry on) and the list is built at the new positions.
void Engine::Impl::Repopulate(std::span<const double> positions, std::span<const double> active) {
  const auto t0 = Clock::now();
  if (model.dimension != k) {
    throw InputError(
        fmt::format("repopulate: the dimension must stay {} (got {})", k, model.dimension));
  }
  model.Validate();
  CheckParticleMemory(k, model.count(), options.memory_limit_bytes);
  n = model.count();
  const auto entries = static_cast<std::size_t>(k) * static_cast<std::size_t>(n);
  if (positions.size() != entries) {
    throw InputError(fmt::format("repopulate: positions have {} entries for {} particles in {}D",
                                 positions.size(), n, k));
  }
  if (!active.empty() && active.size() != entries) {
    throw InputError(
        fmt::format("repopulate: active velocities have {} entries for {} particles in {}D",
                    active.size(), n, k));
  }
  for (double v : positions) {
    if (!std::isfinite(v)) throw InputError("repopulate: positions must be finite");
  }
  if (options.threads <= 0 && !lexicographic) {
    threads = std::clamp(n / 20000, 1, std::max(1, omp_get_max_threads()));
  }
  rmax = model.max_radius();
  attraction_range = PairListWidening(forces, MinRadius(model));
  ConfigureSkin();
  const bool uniform_radius = std::all_of(model.radius.begin(), model.radius.end(),
                                          [&](double r) { return r == model.radius.front(); });
  const bool uniform_mobility =
      model.mobility.empty() ||
      std::all_of(model.mobility.begin(), model.mobility.end(), [](double m) { return m == 1.0; });
  list.AssumeUniformRadius(uniform_radius && n > 0 ? model.radius.front() : 0.0);
  store.emplace(model, positions, active);
  prediction.emplace(forces, box, n, options.h, options.seed, uniform_mobility);
  sweep.emplace(model, uniform_radius);
  Rebuild(&store->current, step);
  stats.total_seconds += Seconds(t0, Clock::now());
}

// Sweeps at fixed positions (no drift, no noise) until every pair overlap is ≤ tolerance.
int Engine::Impl::Relax(double tolerance, int max_sweeps) {
  const auto t0 = Clock::now();
  const FreshCurrentOnExit fresh{this};
  int done = 0;
  while (done < max_sweeps && MaxOverlap() > tolerance) {
    store->predicted = store->current;
    list.MarkPredicted();
    double moved = list.BoundAfterPrediction(0.0, store->predicted.data(), threads);
    if (list.NeedsBuild(moved, true)) {
      list.RelaxSkin();
      Rebuild(&store->predicted, step);
      moved = 0.0;
    }
    SweepUntilAccepted(moved, 1, true);
    store->current.swap(store->predicted);
    current_stale = false;
    ++done;
  }
  stats.total_seconds += Seconds(t0, Clock::now());
  return done;
}

// ---------------------------------------------------------------------------------------------
// Engine.

Engine::Engine(ParticleModel model, Forces forces, EngineOptions options,
               std::span<const double> positions)
    : impl_(std::make_unique<Impl>()) {
  const auto t0 = Clock::now();
  impl_->model = std::move(model);
  impl_->forces = std::move(forces);
  impl_->options = options;
  impl_->Setup(positions);
  impl_->stats.setup_seconds = Seconds(t0, Clock::now());
  impl_->stats.neighbour_seconds = 0.0;
}

Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

bool Engine::Step() { return impl_->Step(); }

void Engine::Repopulate(ParticleModel model, std::span<const double> positions,
                        std::span<const double> active_velocity) {
  impl_->model = std::move(model);
  impl_->Repopulate(positions, active_velocity);
}

int Engine::Relax(double tolerance, int max_sweeps) {
  if (!(tolerance >= 0.0)) {
    throw InputError(fmt::format("relax tolerance must be ≥ 0 (got {})", tolerance));
  }
  return impl_->Relax(tolerance, max_sweeps);
}

EngineSummary Engine::Run(double T, const EngineObserver& observer) {
  const std::int64_t steps = StepCount(T, impl_->options.h);
  if (observer) observer(*this);
  return RunTo(impl_->step + steps, observer);
}

EngineSummary Engine::Continue(double T, const EngineObserver& observer) {
  return RunTo(StepCount(T, impl_->options.h), observer);
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
    if (observer) observer(*this);
  }
  return summary();
}

void Engine::CopyPositions(std::span<double> out) const {
  impl_->store->CopyPositionsById(impl_->box, out, impl_->threads);
}

std::vector<double> Engine::Positions() const {
  std::vector<double> x(impl_->store->current.size());
  CopyPositions(x);
  return x;
}

StoredPositions Engine::Stored() const { return {impl_->store->id, impl_->store->current}; }

int Engine::dimension() const { return impl_->k; }
int Engine::count() const { return impl_->n; }
std::int64_t Engine::step() const { return impl_->step; }
double Engine::time() const { return static_cast<double>(impl_->step) * impl_->options.h; }
int Engine::threads() const { return impl_->threads; }
const ParticleModel& Engine::model() const { return impl_->model; }
const Forces& Engine::forces() const { return impl_->forces; }
const EngineOptions& Engine::options() const { return impl_->options; }

EngineSummary Engine::summary() const {
  EngineSummary s;
  s.stats = impl_->stats;
  s.settings = impl_->options;
  s.termination = impl_->termination;
  s.message = impl_->message;
  s.failed_step = impl_->failed_step;
  s.failed_particle = impl_->failed_particle;
  return s;
}

double Engine::MaxPairOverlap() const { return impl_->MaxOverlap(); }

double Engine::MaxViolation() const {
  return std::max(
      impl_->MaxOverlap(),
      impl_->sweep->MaxFixedViolation(impl_->store->current.data(), impl_->store->radius.data()));
}

std::vector<std::pair<int, int>> Engine::CandidatePairs() const {
  const Impl& m = *impl_;
  const int* row_start = m.list.row_start();
  const int* nbr = m.list.neighbours();
  const std::vector<int>& id = m.store->id;
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(static_cast<std::size_t>(m.list.pairs()));
  for (int s = 0; s < m.n; ++s) {
    for (int p = row_start[s]; p < row_start[s + 1]; ++p) {
      const int a = id[static_cast<std::size_t>(s)];
      const int b = id[static_cast<std::size_t>(nbr[p])];
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<int> Engine::ContactCounts(double factor) const {
  if (!(factor >= 1.0 && factor <= 1.5)) {
    throw InputError(fmt::format("contact factor must be in [1, 1.5] (got {})", factor));
  }
  const Impl& m = *impl_;
  std::vector<int> counts(static_cast<std::size_t>(m.n), 0);
  const int* row_start = m.list.row_start();
  const int* nbr = m.list.neighbours();
  const double* x = m.store->current.data();
  const double* r = m.store->radius.data();
  const int* id = m.store->id.data();
  internal::DispatchDimensionPeriodic(m.k, m.box.any, [&](auto k, auto p) {
    for (int s = 0; s < m.n; ++s) {
      for (int q = row_start[s]; q < row_start[s + 1]; ++q) {
        const int t = nbr[q];
        double u[3];
        m.list.Displacement<k, p>(x, s, t, q, u);
        double d2 = 0.0;
        for (int a = 0; a < k; ++a) d2 += u[a] * u[a];
        const double reach = factor * (r[s] + r[t]);
        if (d2 <= reach * reach) {
          ++counts[static_cast<std::size_t>(id[s])];
          ++counts[static_cast<std::size_t>(id[t])];
        }
      }
    }
  });
  return counts;
}

int FixOverlaps(const ParticleModel& model, std::span<double> positions,
                const FixOverlapsOptions& options) {
  if (!(options.tolerance >= 0.0)) {
    throw InputError(fmt::format("tolerance must be ≥ 0 (got {})", options.tolerance));
  }
  if (options.max_sweeps < 1) {
    throw InputError(fmt::format("max_sweeps must be ≥ 1 (got {})", options.max_sweeps));
  }
  EngineOptions eo;
  eo.h = 1.0;
  eo.order = options.order;
  eo.threads = options.threads;
  eo.check_initial_state = false;
  eo.monitor_overlap = false;
  eo.skin_factor = 1.0;
  Engine engine(model, Forces{}, eo, positions);
  const double rmin = *std::min_element(model.radius.begin(), model.radius.end());
  const double tol = options.tolerance * rmin;
  int sweeps = 0;
  while (engine.MaxViolation() > tol) {
    if (sweeps >= options.max_sweeps) {
      throw NumericalError(fmt::format("FixOverlaps: still a violation of {} after {} sweeps",
                                       engine.MaxViolation(), sweeps));
    }
    engine.Step();
    ++sweeps;
  }
  engine.CopyPositions(positions);
  return sweeps;
}

}  // namespace moreau::particles
