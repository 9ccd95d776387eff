// Regression checks on bits: the final positions of the crowd example (examples/crowd.toml at
// T = 4 instead of 45) hash to a recorded value (the noise of forces.h with its vectorised
// Box–Muller normals; `moreau run examples/crowd.toml --set problem.T=4.0` prints it as
// positions_hash).
#include <gtest/gtest.h>

#include "moreau/common/hash.h"
#include "moreau/common/random.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"

namespace moreau::particles {
namespace {

TEST(PositionsHash, CrowdExampleKeepsItsBits) {
  constexpr std::uint64_t kSeed = 7;
  ParticleModel model;
  model.dimension = 2;
  SplitMix64 rng(kSeed ^ 0x5DEECE66DULL);  // the CLI's polydisperse radii
  for (int i = 0; i < 200; ++i) model.radius.push_back(0.2 + (0.3 - 0.2) * rng.Uniform01());
  model.domain_lo = {0.5, 0.5, 0.0};
  model.domain_hi = {14.5, 14.5, 1.0};
  const Room room{15.0, 15.0, 1.2};
  AddRoom(room, &model);
  Forces forces;
  forces.propulsion = room.WalkToTheDoor(1.3);
  forces.diffusion = 0.005;
  EngineOptions options;
  options.h = 0.002;
  options.seed = kSeed;
  options.sweeps = 8;
  options.skin_factor = 2.0;
  const std::vector<double> x0 =
      RandomSequentialAddition(model, model.domain_lo, model.domain_hi, kSeed);
  Engine engine(model, forces, options, x0);
  // The count from the stored positions (no copy) and from copies in id order agree.
  EvacuationCount out(room, model.count());
  EvacuationCount out_by_id(room, model.count());
  const EngineSummary summary = engine.Run(4.0, [&](const Engine& e) {
    const StoredPositions stored = e.Stored();
    out.Update(stored.ids, stored.positions);
    out_by_id.Update(e.Positions());
    return true;
  });
  ASSERT_TRUE(summary.ok()) << summary.message;
  EXPECT_EQ(out.out(), 14);  // "people out at t = 4: 14 of 200"
  EXPECT_EQ(out_by_id.out(), 14);
  EXPECT_EQ(HashDoublesHex(engine.Positions()), "c0e6159c7765642d");
}

}  // namespace
}  // namespace moreau::particles
