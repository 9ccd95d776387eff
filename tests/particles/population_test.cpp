// The population rules on the engine: determinism across threads, ids, a pure-birth process
// against its expectation, overlap after divisions, removal, bad input.
#include "moreau/particles/population.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "particles/population_test_util.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::BruteForceMaxOverlap;
using testing::Colony;
using testing::ExpectInputError;
using testing::GrowingColony;
using testing::Make;
using testing::SameBits;

// A 2D colony of agents of one type, h = 0.01, without noise; the agents and positions to set.
Colony OneTypeColony(const AgentType& type, int interval) {
  Colony c;
  c.geometry.dimension = 2;
  c.options.h = 0.01;
  c.rules.types = {type};
  c.rules.interval = interval;
  return c;
}

std::vector<std::int64_t> Ids(const Population& p) {
  std::vector<std::int64_t> ids;
  for (const Agent& a : p.agents()) ids.push_back(a.id);
  return ids;
}

TEST(Population, DivisionAndDeathAreBitIdenticalOnOneAndTwoThreadsSlow) {
  Colony c = GrowingColony();
  c.options.threads = 1;
  Population one = Make(c);
  const PopulationSummary s1 = one.Run(8.0);
  c.options.threads = 2;
  Population two = Make(c);
  const PopulationSummary s2 = two.Run(8.0);
  ASSERT_TRUE(s1.ok()) << s1.message;
  EXPECT_GT(s1.births, 20);
  EXPECT_GT(s1.deaths, 0);
  EXPECT_EQ(s1.births, s2.births);
  EXPECT_EQ(s1.deaths, s2.deaths);
  EXPECT_EQ(Ids(one), Ids(two));
  EXPECT_TRUE(SameBits(one.Positions(), two.Positions()));
  for (std::size_t i = 0; i < one.agents().size(); ++i) {
    EXPECT_EQ(one.agents()[i].radius, two.agents()[i].radius);
    EXPECT_EQ(one.agents()[i].polarity, two.agents()[i].polarity);
  }
}

TEST(Population, IdsAreUniqueReproducibleAndPureFunctionsOfTheMother) {
  const Colony c = GrowingColony();
  Population a = Make(c);
  Population b = Make(c);
  // Every id ever seen, with its lineage: a new id must equal ChildId(mother, its count).
  std::set<std::int64_t> seen;
  for (const Agent& x : a.agents()) seen.insert(x.id);
  for (int i = 0; i < 1600; ++i) {
    const std::vector<Agent> before = a.agents();
    a.Step();
    b.Step();
    if (a.agents().size() == before.size() && i % 50 != 0) continue;
    std::set<std::int64_t> now;
    for (std::size_t j = 0; j < a.agents().size(); ++j) {
      const Agent& x = a.agents()[j];
      ASSERT_TRUE(now.insert(x.id).second) << "id " << x.id << " twice";
      if (seen.insert(x.id).second) {  // born now: right after its mother
        ASSERT_GT(j, 0u);
        const Agent& mother = a.agents()[j - 1];
        EXPECT_EQ(x.id, ChildId(mother.id, mother.divisions));
        EXPECT_EQ(x.generation, mother.generation);
      }
    }
  }
  EXPECT_GT(a.count(), 20);
  EXPECT_EQ(Ids(a), Ids(b));
}

TEST(Population, PureBirthCountMatchesItsExpectedExponentialGrowthOverSeeds) {
  // Each agent divides with probability p = 1 − e^{−λΔt} per rule step, so the count is a
  // Galton–Watson process with offspring 1 or 2: E[N_n] = N0 μ^n, μ = 1 + p, and
  // Var[N_n] = N0 σ² μ^{n−1} (μ^n − 1)/(μ − 1), σ² = p(1 − p). (μ^n → e^{λt} as Δt → 0.)
  AgentType cell;
  cell.radius = 0.5;
  cell.division_rate = 1.0;
  Colony c = OneTypeColony(cell, 10);
  c.types = {0, 0, 0, 0};
  c.x0 = {0.0, 0.0, 20.0, 0.0, 0.0, 20.0, 20.0, 20.0};
  const int rule_steps = 25;
  const double T = rule_steps * c.rules.interval * c.options.h;
  const double p = -std::expm1(-1.0 * c.rules.interval * c.options.h);
  const double mu = 1.0 + p;
  const double n0 = 4.0;
  const double mean = n0 * std::pow(mu, rule_steps);
  const double var = n0 * p * (1.0 - p) * std::pow(mu, rule_steps - 1) *
                     (std::pow(mu, rule_steps) - 1.0) / (mu - 1.0);
  const int seeds = 40;
  double sum = 0.0;
  for (int s = 0; s < seeds; ++s) {
    c.rules.seed = 1000 + static_cast<std::uint64_t>(s);
    Population pop = Make(c);
    const PopulationSummary summary = pop.Run(T);
    ASSERT_TRUE(summary.ok()) << summary.message;
    ASSERT_EQ(summary.rule_steps, rule_steps);
    sum += pop.count();
  }
  const double standard_error = std::sqrt(var / seeds);
  EXPECT_NEAR(sum / seeds, mean, 4.0 * standard_error)
      << "expected " << mean << " ± " << standard_error;
}

TEST(Population, NoOverlapBeyondTheToleranceAfterDivisions) {
  Colony c = GrowingColony();
  c.rules.types[0].death_rate = 0.0;
  c.rules.types[1].death_rate = 0.0;
  c.rules.relax = true;
  c.rules.relax_tolerance = 1e-3;
  Population pop = Make(c);
  std::int64_t checked = 0;
  const double tol = c.rules.relax_tolerance * 0.5;
  const PopulationSummary s = pop.Run(16.0, [&](const Population& p) {
    ParticleModel m = p.engine().model();
    const double brute = BruteForceMaxOverlap(m, p.Positions());
    EXPECT_LE(brute, tol * (1.0 + 1e-12)) << "step " << p.engine().step();
    EXPECT_NEAR(p.engine().MaxPairOverlap(), brute, 1e-12);
    ++checked;
    return true;
  });
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_GT(s.births, 50);
  EXPECT_GT(s.relax_sweeps, 0);
  EXPECT_GT(s.max_overlap_before, 10.0 * tol);  // the divisions did overlap before relaxing
  EXPECT_EQ(checked, s.rule_steps + 1);
}

TEST(Population, RemovedAgentsLeaveNoTraceInTheLists) {
  // Agents pushed along +x by a constant force leave through the plane x = 5.
  Colony c;
  c.geometry.dimension = 2;
  c.options.h = 0.01;
  c.forces.constant_force = {1.0, 0.0, 0.0};
  AgentType walker;
  walker.radius = 0.4;
  walker.death_rate = 0.05;
  c.rules.types = {walker};
  c.rules.interval = 2;
  c.rules.exit = ExitPlane{{1.0, 0.0, 0.0}, 5.0};
  for (int i = 0; i < 30; ++i) {
    c.types.push_back(0);
    c.x0.push_back(-1.0 * (i % 10));
    c.x0.push_back(1.0 * (i / 10));
  }
  Population pop = Make(c);
  std::set<std::int64_t> gone;
  std::vector<std::int64_t> previous = Ids(pop);
  const PopulationSummary s = pop.Run(12.0, [&](const Population& p) {
    const std::vector<std::int64_t> ids = Ids(p);
    const std::set<std::int64_t> now(ids.begin(), ids.end());
    for (std::int64_t id : previous) {
      if (!now.contains(id)) gone.insert(id);
    }
    previous = ids;
    const Engine& e = p.engine();
    EXPECT_EQ(e.count(), p.count());
    EXPECT_EQ(e.model().stable_ids, ids);
    for (std::int64_t id : e.model().stable_ids) EXPECT_FALSE(gone.contains(id));
    for (const auto& [i, j] : e.CandidatePairs()) {
      EXPECT_LT(j, p.count());
      EXPECT_GE(i, 0);
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
      EXPECT_EQ(e.model().radius[i], p.agents()[i].radius);
    }
    return true;
  });
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_GT(s.removals, 10);
  EXPECT_GT(s.deaths, 0);
  EXPECT_EQ(static_cast<std::int64_t>(gone.size()), s.removals + s.deaths);
}

TEST(Population, ContactInhibitionStopsGrowthOfTouchingAgents) {
  // Two touching agents with c_max = 1 never grow; a lone one grows at g.
  Colony c;
  c.geometry.dimension = 2;
  c.options.h = 0.01;
  AgentType cell;
  cell.radius = 0.5;
  cell.growth_rate = 0.1;
  cell.max_contacts = 1.0;
  c.rules.types = {cell};
  c.types = {0, 0, 0};
  c.x0 = {0.0, 0.0, 1.0, 0.0, 10.0, 0.0};
  Population pop = Make(c);
  ASSERT_TRUE(pop.Run(1.0).ok());
  EXPECT_EQ(pop.agents()[0].radius, 0.5);
  EXPECT_EQ(pop.agents()[1].radius, 0.5);
  EXPECT_NEAR(pop.agents()[2].radius, 0.6, 1e-12);
  EXPECT_EQ(pop.Observe().contacts, 1);
}

// Alignment reads the engine's contacts, periodic images included: a touching pair across a
// periodic boundary (either axis) aligns exactly as the same pair mid-box, and a pair just out of
// reach keeps its polarities.
TEST(Population, AlignmentAcrossAPeriodicBoundaryEqualsAlignmentMidBox) {
  AgentType cell;
  cell.radius = 0.5;
  cell.alignment = 2.0;
  Colony c = OneTypeColony(cell, 1);
  c.geometry.periodic = {true, true, false};
  c.geometry.domain_lo = {0.0, 0.0, 0.0};
  c.geometry.domain_hi = {10.0, 8.0, 1.0};
  c.rules.seed = 8;  // initial polarities nearly perpendicular
  c.types = {0, 0};
  auto aligned = [&](std::vector<double> x0) {  // the polarities after one rule step
    c.x0 = std::move(x0);
    Population pop = Make(c);
    EXPECT_TRUE(pop.Step());
    return std::vector<Vec3>{pop.agents()[0].polarity, pop.agents()[1].polarity};
  };
  const std::vector<Vec3> apart = aligned({2.0, 4.0, 3.1, 4.0});      // 1.1 apart: not touching
  const std::vector<Vec3> mid_box = aligned({4.49, 4.0, 5.51, 4.0});  // 1.02 apart
  EXPECT_EQ(aligned({9.49, 4.0, 0.51, 4.0}), mid_box);
  EXPECT_EQ(aligned({3.0, 0.31, 3.0, 7.29}), mid_box);
  // Alignment turned the two polarities toward each other; apart they stayed as drawn.
  auto cosine = [](const std::vector<Vec3>& p) { return p[0][0] * p[1][0] + p[0][1] * p[1][1]; };
  EXPECT_GT(cosine(mid_box), cosine(apart) + 0.02);
  const Population fresh = Make(c);
  for (std::size_t i = 0; i < 2; ++i) {
    for (std::size_t a = 0; a < 2; ++a) {
      EXPECT_NEAR(apart[i][a], fresh.agents()[i].polarity[a], 1e-15);
    }
  }
}

TEST(Population, AllAgentsGoneEndsTheRunCompleted) {
  Colony c;
  c.geometry.dimension = 2;
  c.options.h = 0.01;
  c.forces.constant_force = {1.0, 0.0, 0.0};
  c.rules.types = {AgentType{}};
  c.rules.exit = ExitPlane{{1.0, 0.0, 0.0}, 0.5};
  c.types = {0};
  c.x0 = {0.0, 0.0};
  Population pop = Make(c);
  const PopulationSummary s = pop.Run(5.0);
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(pop.count(), 0);
  EXPECT_EQ(s.removals, 1);
  EXPECT_NE(s.message.find("no agents left"), std::string::npos);
  EXPECT_LT(s.engine.stats.steps, 500);
}

TEST(Population, BadInputNamesTheField) {
  PopulationRules r;
  r.types = {AgentType{}};
  r.types[0].death_rate = -1.0;
  ExpectInputError([&] { r.Validate(); }, "types.cell.death_rate: must be ≥ 0 (got -1)");
  r.types[0].death_rate = 0.0;
  r.types[0].division_radius = 0.3;
  ExpectInputError([&] { r.Validate(); },
                   "types.cell.division_radius: must be > the radius 0.5 (got 0.3)");
  r.types[0].division_radius = 0.0;
  r.types.push_back(AgentType{});
  ExpectInputError([&] { r.Validate(); }, "the name 'cell' is used twice");
  r.types[1].name = "tumour";
  ExpectInputError([&] { r.TypeIndex("stroma"); }, "unknown type 'stroma' (types: cell, tumour)");
  EXPECT_EQ(r.TypeIndex("tumour"), 1);
  ExpectInputError([&] { ParseDivisionAxis("sideways"); }, "unknown division axis 'sideways'");
  Colony c = GrowingColony();
  c.types[2] = 7;
  ExpectInputError([&] { Make(c); }, "type of agent 2 must be in [0, 2) (got 7)");
}

}  // namespace
}  // namespace moreau::particles
