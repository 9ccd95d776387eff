// Regression check on bits: the final positions of `moreau run examples/disks.toml` (40 disks,
// PBD, h = 0.001, T = 1) hash to a recorded value (the last frame of trajectory.csv, hashed with
// moreau::HashDoubles).
#include <gtest/gtest.h>

#include "moreau/common/hash.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/stepper.h"

namespace moreau::pbd {
namespace {

TEST(PositionsHash, DisksExampleKeepsItsBits) {
  DisksCase c;
  c.count = 40;
  c.radius = 0.1;
  c.gamma = 1.0;
  c.T = 1.0;
  c.seed = 1;
  ParticleConstraints constraints(c.MakeModel());
  StepperOptions o;
  o.h = 0.001;
  Vector x;
  const SimulationSummary s =
      Simulate(*c.MakeDrift(), constraints, o, c.InitialState(), c.T, {}, &x);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(HashDoublesHex({x.data(), static_cast<std::size_t>(x.size())}), "28cc547bd51648cc");
  EXPECT_EQ(constraints.neighbour_stats().neighbour_list_builds, 29);  // as summary.json said
}

}  // namespace
}  // namespace moreau::pbd
