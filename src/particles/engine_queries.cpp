// What the engine answers between steps: positions, the summary, overlaps and violations, the
// candidate pairs and the contacts (the engine's one definition of touching), and FixOverlaps.
#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/engine.h"
#include "particles/engine_impl.h"

namespace moreau::particles {

namespace {

void CheckContactFactor(double factor) {
  if (!(factor >= 1.0 && factor <= 1.5)) {
    throw InputError(fmt::format("contact factor must be in [1, 1.5] (got {})", factor));
  }
}

// The pair of slots (s, t) as particle ids (smaller first).
std::pair<int, int> IdPair(const std::vector<int>& id, int s, int t) {
  const int a = id[static_cast<std::size_t>(s)];
  const int b = id[static_cast<std::size_t>(t)];
  return {std::min(a, b), std::max(a, b)};
}

// Calls f(s, t) for the pairs (s, t) of `list` with ‖x_s − x_t‖ ≤ factor (r_s + r_t), the
// pair's image on periodic axes.
template <typename F>
void ForEachListContact(const internal::NeighbourList& list, const double* x, const double* r,
                        int n, double factor, F&& f) {
  const int* row_start = list.row_start();
  const int* nbr = list.neighbours();
  internal::DispatchDimensionPeriodic(list.box().k, list.box().any, [&](auto k, auto p) {
    for (int s = 0; s < n; ++s) {
      for (int q = row_start[s]; q < row_start[s + 1]; ++q) {
        const int t = nbr[q];
        double u[3];
        list.template Displacement<k, p>(x, s, t, q, u);
        double d2 = 0.0;
        for (int a = 0; a < k; ++a) d2 += u[a] * u[a];
        const double reach = factor * (r[s] + r[t]);
        if (d2 <= reach * reach) f(s, t);
      }
    }
  });
}

}  // namespace

// The engine's list holds every touching pair while (factor − 1) 2 r_max stays below its
// coverage beyond contact (NeighbourList::coverage); otherwise, or after a failed step, a list
// of the pairs within that reach is built for the query at the current positions (wrapped).
template <typename F>
void Engine::Impl::ForEachContact(double factor, F&& f) const {
  const internal::StepContext& c = context;
  if (c.n == 0) return;
  const double beyond = (factor - 1.0) * 2.0 * c.rmax;
  if (termination == Termination::kCompleted && beyond < c.list.coverage()) {
    ForEachListContact(c.list, c.store->current.data(), c.store->radius.data(), c.n, factor, f);
    return;
  }
  std::vector<double> x = c.store->current;
  c.box.WrapAll(x.data(), c.n);
  internal::LexicographicPairList pairs(c.box, c.n, c.rmax, beyond * (1.0 + 1e-9) + 1e-9 * c.rmax);
  pairs.Build(x.data(), c.store->radius.data());
  ForEachListContact(pairs.list(), x.data(), c.store->radius.data(), c.n, factor, f);
}

void Engine::CopyPositions(std::span<double> out) const {
  impl_->context.store->CopyPositionsById(impl_->context.box, out, impl_->context.threads);
}

std::vector<double> Engine::Positions() const {
  std::vector<double> x(impl_->context.store->current.size());
  CopyPositions(x);
  return x;
}

StoredPositions Engine::Stored() const {
  return {impl_->context.store->id, impl_->context.store->current};
}

int Engine::dimension() const { return impl_->context.k; }
int Engine::count() const { return impl_->context.n; }
std::int64_t Engine::step() const { return impl_->step; }
double Engine::time() const { return static_cast<double>(impl_->step) * impl_->context.options.h; }
int Engine::threads() const { return impl_->context.threads; }
const ParticleModel& Engine::model() const { return impl_->context.model; }
const Forces& Engine::forces() const { return impl_->forces; }
const EngineOptions& Engine::options() const { return impl_->context.options; }

EngineSummary Engine::summary() const {
  EngineSummary s;
  s.stats = impl_->Stats();
  s.settings = impl_->context.options;
  s.termination = impl_->termination;
  s.message = impl_->message;
  s.failed_step = impl_->failed_step;
  s.failed_particle = impl_->failed_particle;
  return s;
}

double Engine::MaxPairOverlap() const { return impl_->MaxOverlap(); }

double Engine::MaxViolation() const {
  const internal::ParticleStore& store = *impl_->context.store;
  return std::max(impl_->MaxOverlap(),
                  impl_->sweep->MaxFixedViolation(store.current.data(), store.radius.data()));
}

std::vector<std::pair<int, int>> Engine::CandidatePairs() const {
  const internal::StepContext& c = impl_->context;
  const int* row_start = c.list.row_start();
  const int* nbr = c.list.neighbours();
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(static_cast<std::size_t>(c.list.pairs()));
  for (int s = 0; s < c.n; ++s) {
    for (int p = row_start[s]; p < row_start[s + 1]; ++p) {
      pairs.push_back(IdPair(c.store->id, s, nbr[p]));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::pair<int, int>> Engine::Contacts(double factor) const {
  CheckContactFactor(factor);
  const std::vector<int>& id = impl_->context.store->id;
  std::vector<std::pair<int, int>> pairs;
  impl_->ForEachContact(factor, [&](int s, int t) { pairs.push_back(IdPair(id, s, t)); });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<int> Engine::ContactCounts(double factor) const {
  CheckContactFactor(factor);
  const int* id = impl_->context.store->id.data();
  std::vector<int> counts(static_cast<std::size_t>(impl_->context.n), 0);
  impl_->ForEachContact(factor, [&](int s, int t) {
    ++counts[static_cast<std::size_t>(id[s])];
    ++counts[static_cast<std::size_t>(id[t])];
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
