// Bad input is an InputError whose message names the field.
#include <gtest/gtest.h>

#include <limits>

#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

ParticleModel TwoDisks() {
  ParticleModel m;
  m.radius = {0.5, 0.5};
  return m;
}

const std::vector<double> kApart = {0.0, 0.0, 2.0, 0.0};

void Make(const ParticleModel& m, const std::vector<double>& x, Forces f = {},
          EngineOptions o = {}) {
  Engine e(m, f, o, x);
}

TEST(ParticleInput, ModelFields) {
  ParticleModel m = TwoDisks();
  m.radius[1] = -1.0;
  ExpectInputError([&] { Make(m, kApart); }, "radius of particle 1 must be > 0");
  m = TwoDisks();
  m.mobility = {1.0, 0.0};
  ExpectInputError([&] { Make(m, kApart); }, "mobility of particle 1 must be > 0");
  m.mobility = {1.0};
  ExpectInputError([&] { Make(m, kApart); }, "mobility has 1 entries for 2 particles");
  m = TwoDisks();
  m.dimension = 4;
  ExpectInputError([&] { Make(m, kApart); }, "dimension must be 2 or 3");
  m = TwoDisks();
  m.walls.push_back(Wall{{0, 0, 0}, 0});
  ExpectInputError([&] { Make(m, kApart); }, "walls[0].normal must be non-zero");
  m = TwoDisks();
  m.spheres.push_back(SphereObstacle{{5, 5, 0}, 0.0});
  ExpectInputError([&] { Make(m, kApart); }, "spheres[0].radius must be > 0");
  m = TwoDisks();
  m.segments.push_back(SegmentObstacle{{1, 1}, {1, 1}});
  ExpectInputError([&] { Make(m, kApart); }, "segments[0] needs a ≠ b");
  m = TwoDisks();
  m.dimension = 3;
  m.segments.push_back(SegmentObstacle{{1, 1}, {2, 1}});
  ExpectInputError([&] { Make(m, {0, 0, 0, 2, 0, 0}); }, "segments need dimension 2");
  m = ParticleModel{};
  ExpectInputError([&] { Make(m, {}); }, "at least one particle");
}

TEST(ParticleInput, RadiusTooLargeForThePeriodicDomain) {
  ParticleModel m = TwoDisks();
  m.periodic = {true, false, false};
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {1.5, 1, 1};
  ExpectInputError(
      [&] {
        Make(m, {0.0, 0.0, 0.75, 5.0});
      },
      "radius of particle 0 (0.5) is too large for periodic axis 0");
  m.domain_hi = {0.0, 1, 1};
  ExpectInputError([&] { Make(m, kApart); }, "domain of periodic axis 0 needs lo < hi");
}

TEST(ParticleInput, CountThatDoesNotFitInMemoryIsRejectedBeforeAllocating) {
  ExpectInputError([] { CheckParticleMemory(2, 1000000000, std::int64_t{1} << 30); },
                   "1000000000 particles need about");
  ExpectInputError([] { CheckParticleMemory(3, std::int64_t{1} << 40); },
                   "more than the engine's limit of 2^31");
  EXPECT_NO_THROW(CheckParticleMemory(2, 1000000));
  EngineOptions o;
  o.memory_limit_bytes = 100;  // two particles need more than 100 bytes
  ExpectInputError([&] { Make(TwoDisks(), kApart, {}, o); },
                   "2 particles need about 576 B, more than the 100 B available");
}

TEST(ParticleInput, InfeasibleInitialStates) {
  ExpectInputError([] { Make(TwoDisks(), {0.0, 0.0, 0.9, 0.0}); }, "particles 0 and 1 overlap by");
  ParticleModel m = TwoDisks();
  m.walls.push_back(Wall{{0, 1, 0}, -0.2});  // y ≥ −0.2 + r
  ExpectInputError([&] { Make(m, kApart); }, "particle 0 is inside walls[0]");
  m = TwoDisks();
  m.spheres.push_back(SphereObstacle{{2.0, 1.0, 0}, 0.7});
  ExpectInputError([&] { Make(m, kApart); }, "particle 1 is inside spheres[0]");
  m = TwoDisks();
  m.segments.push_back(SegmentObstacle{{-1, 0.3}, {1, 0.3}});
  ExpectInputError([&] { Make(m, kApart); }, "particle 0 is inside segments[0]");
  ExpectInputError([] { Make(TwoDisks(), {0.0, 0.0, 2.0}); }, "positions have 3 entries");
  ExpectInputError(
      [] {
        Make(TwoDisks(), {0.0, 0.0, std::numeric_limits<double>::quiet_NaN(), 0.0});
      },
      "position of particle 1 is not finite");
  // Periodic: a pair overlapping across the boundary.
  m = TwoDisks();
  m.periodic = {true, false, false};
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {10, 1, 1};
  ExpectInputError([&] { Make(m, {0.2, 0.0, 9.5, 0.0}); }, "particles 0 and 1 overlap");
}

TEST(ParticleInput, OptionsAndForces) {
  EngineOptions o;
  o.h = 0.0;
  ExpectInputError([&] { Make(TwoDisks(), kApart, {}, o); }, "h: must be > 0 (got 0)");
  o = {};
  o.skin_factor = -1;
  ExpectInputError([&] { Make(TwoDisks(), kApart, {}, o); }, "skin_factor: must be > 0");
  Forces f;
  f.diffusion = -1;
  ExpectInputError([&] { Make(TwoDisks(), kApart, f); }, "forces.diffusion must be ≥ 0");
  f = {};
  f.attraction = PairAttraction{1.0, 0.0, {}};
  ExpectInputError([&] { Make(TwoDisks(), kApart, f); }, "forces.attraction.range must be > 0");
  f = {};
  f.propulsion = SelfPropulsion{-1.0, {0, 0, 0}, std::nullopt, std::nullopt, std::nullopt, nullptr};
  ExpectInputError([&] { Make(TwoDisks(), kApart, f); }, "forces.propulsion.speed must be ≥ 0");
  f = {};
  f.trap = HarmonicTrap{-1.0, {0, 0, 0}};
  ExpectInputError([&] { Make(TwoDisks(), kApart, f); }, "forces.trap.gamma must be ≥ 0");
  ExpectInputError([] { ParseSweepOrder("random"); }, "unknown sweep order 'random'");
  EXPECT_EQ(ParseSweepOrder(SweepOrderName(SweepOrder::kLexicographic)),
            SweepOrder::kLexicographic);
}

}  // namespace
}  // namespace moreau::particles
