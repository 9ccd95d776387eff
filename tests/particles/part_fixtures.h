// Random particle configurations for the tests of the engine's parts (cell list, neighbour list,
// colouring, prediction), and the step context the parts read, set up for them alone.
#pragma once

#include <vector>

#include "moreau/common/random.h"
#include "moreau/particles/engine.h"
#include "particles/step_context.h"

namespace moreau::particles::testing {

// N polydisperse particles (radii in [0.2, 0.6)) placed by random sequential addition in
// [0, L]^k, periodic on the given axes.
struct RandomConfiguration {
  ParticleModel model;
  std::vector<double> x;

  RandomConfiguration(int k, std::array<bool, 3> periodic, int n, double L, std::uint64_t seed) {
    model.dimension = k;
    SplitMix64 rng(seed);
    for (int i = 0; i < n; ++i) model.radius.push_back(0.2 + 0.4 * rng.Uniform01());
    model.periodic = periodic;
    model.domain_lo = {0, 0, 0};
    model.domain_hi = {L, L, L};
    x = RandomSequentialAddition(model, {0, 0, 0}, {L, L, L}, seed + 1);
  }
};

// *c: the step context of `model` at x in the lexicographic layout (slots = ids, rows sorted, one
// thread): the store at x (current and predicted positions), the cell list for pairs within
// `reach` with blocks of block_cells (0: automatic), its colouring, and the neighbour list with
// the given skin built at x.
inline void LexicographicContext(const ParticleModel& model, const std::vector<double>& x,
                                 double reach, double skin, int block_cells,
                                 internal::StepContext* c) {
  c->model = model;
  c->k = model.dimension;
  c->n = model.count();
  c->threads = 1;
  c->lexicographic = true;
  c->rmax = model.max_radius();
  c->box = internal::PeriodicBox::Of(model);
  c->store.emplace(model, x);
  c->store->predicted = x;
  c->cells.Fit(x.data(), c->n, c->box, reach, block_cells, 1);
  c->cells.Sort(x.data(), c->store->id.data(), c->n, 1);
  c->colouring.Assign(c->cells);
  c->list.Configure(c->box, c->n, skin, 1e300, 0.0);
  c->list.Build(*c, x.data(), 0);
}

}  // namespace moreau::particles::testing
