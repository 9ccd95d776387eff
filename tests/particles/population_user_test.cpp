// User code on a population (population.h: UserDrift, UserRule, user variables): the drift's
// displacement against its exact value, the marks of a rule, the variables' inheritance (an
// amount split at divisions is conserved), bad rules and drifts, and the same bits on one and
// two threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "moreau/particles/population.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::BruteForceMaxOverlap;
using testing::ExpectInputError;

// n agents of one type on a line 2 apart (no contacts), no noise, h = 0.01.
Population Line(int n, const AgentType& type, int interval, int threads = 1,
                std::vector<AgentVariable> variables = {}) {
  ParticleModel geometry;
  geometry.dimension = 2;
  EngineOptions options;
  options.h = 0.01;
  options.threads = threads;
  PopulationRules rules;
  rules.types = {type};
  rules.interval = interval;
  rules.variables = std::move(variables);
  std::vector<double> x;
  for (int i = 0; i < n; ++i) x.insert(x.end(), {2.0 * i, 0.0});
  return Population(geometry, Forces{}, options, rules, std::vector<int>(n, 0), x);
}

TEST(PopulationUserCode, AConstantDriftMovesEachAgentByStepsTimesHTimesItsVelocity) {
  Population p = Line(3, AgentType{}, 1000);
  p.SetDrift([](const PopulationView& view, std::span<double> v) {
    for (std::size_t i = 0; i < view.agents.size(); ++i)
      v[2 * i + 1] = 0.5 * static_cast<double>(i);
  });
  for (int s = 0; s < 40; ++s) ASSERT_TRUE(p.Step());
  const std::vector<double> x = p.Positions();
  for (int i = 0; i < 3; ++i) {
    double y = 0.0;  // the same sums the engine does: y ← y + h v
    for (int s = 0; s < 40; ++s) y += 0.01 * (0.5 * i);
    EXPECT_EQ(x[2 * static_cast<std::size_t>(i) + 1], y) << i;
    EXPECT_EQ(x[2 * static_cast<std::size_t>(i)], 2.0 * i);
  }
}

TEST(PopulationUserCode, RemovingTheDriftStopsItsMotion) {
  Population p = Line(1, AgentType{}, 1000);
  p.SetDrift([](const PopulationView&, std::span<double> v) { v[0] = 1.0; });
  ASSERT_TRUE(p.Step());
  p.SetDrift({});
  ASSERT_TRUE(p.Step());
  ASSERT_TRUE(p.Step());
  EXPECT_DOUBLE_EQ(p.Positions()[0], 0.01);
}

TEST(PopulationUserCode, MarkedAgentsDivideAndDieAndSplitVariablesAreConserved) {
  AgentType cell;
  cell.radius = 0.4;
  Population p = Line(4, cell, 5, 1,
                      {{"amount", 8.0, Inheritance::kSplit}, {"clock", 3.0, Inheritance::kCopy}});
  int calls = 0;
  p.SetRule([&](PopulationView& view, std::span<std::uint8_t> divide, std::span<std::uint8_t> die) {
    ++calls;
    EXPECT_EQ(view.step % 5, 0);
    EXPECT_DOUBLE_EQ(view.rule_dt, 0.05);
    ASSERT_EQ(view.variables.size(), 2u);
    if (calls == 1) {
      divide[0] = divide[1] = 1;  // 4 → 6 agents
      die[3] = 1;                 // → 5
      view.variables[1][2] = 7.0;
    }
  });
  for (int s = 0; s < 10; ++s) ASSERT_TRUE(p.Step());
  EXPECT_EQ(calls, 2);
  ASSERT_EQ(p.count(), 5);
  const PopulationSummary s = p.summary();
  EXPECT_EQ(s.births, 2);
  EXPECT_EQ(s.deaths, 1);
  const std::span<const double> amount = p.variable(p.VariableIndex("amount"));
  const std::span<const double> clock = p.variable(1);
  // Mothers and daughters: 4 + 4 (halves of 8), then agent 2 keeps 8; agent 3 died.
  EXPECT_EQ(std::vector<double>(amount.begin(), amount.end()),
            (std::vector<double>{4.0, 4.0, 4.0, 4.0, 8.0}));
  EXPECT_EQ(std::accumulate(amount.begin(), amount.end(), 0.0), 3 * 8.0);
  EXPECT_EQ(std::vector<double>(clock.begin(), clock.end()),
            (std::vector<double>{3.0, 3.0, 3.0, 3.0, 7.0}));
  EXPECT_EQ(p.agents()[1].generation, 1);  // the first daughter, right after its mother
  EXPECT_LT(BruteForceMaxOverlap(p.engine().model(), p.Positions()),
            0.4);  // daughters touch, nothing collapses
}

TEST(PopulationUserCode, BadRulesAndDriftsAreNamed) {
  Population p = Line(2, AgentType{}, 1);
  p.SetRule([](PopulationView& view, std::span<std::uint8_t>, std::span<std::uint8_t>) {
    view.agents[1].radius = -1.0;
  });
  ExpectInputError([&] { p.Step(); }, "radius -1");
  Population q = Line(2, AgentType{}, 1);
  q.SetRule([](PopulationView& view, std::span<std::uint8_t>, std::span<std::uint8_t>) {
    view.agents[0].type = 3;
  });
  ExpectInputError([&] { q.Step(); }, "type 3");
  ExpectInputError([&] { (void)q.VariableIndex("oxygen"); }, "unknown variable 'oxygen'");
  Population r = Line(2, AgentType{}, 100);
  ASSERT_TRUE(r.Step());
  const std::vector<double> before = r.Positions();
  r.SetDrift([](const PopulationView&, std::span<double> v) { v[3] = std::nan(""); });
  EXPECT_FALSE(r.Step());
  const PopulationSummary s = r.summary();
  EXPECT_EQ(s.termination, Termination::kNonFinite);
  EXPECT_NE(s.message.find("agent 1 (id 1)"), std::string::npos) << s.message;
  EXPECT_EQ(r.Positions(), before);  // the last good state
  PopulationRules twice;
  twice.types = {AgentType{}};
  twice.variables = {{"a"}, {"a"}};
  ExpectInputError([&] { twice.Validate(); }, "'a' is used twice");
}

// A rule that throws leaves its rule step pending: the next Step calls it again at the same
// step count, before its own engine step, and the run ends with the bits of one never stopped.
TEST(PopulationUserCode, ARuleThatThrowsIsCalledAgainAtTheSameStep) {
  AgentType cell;
  cell.growth_rate = 0.5;
  cell.division_radius = 0.52;
  std::vector<std::int64_t> seen;
  auto rule = [&](bool throw_once) {
    return [&seen, throw_once](PopulationView& view, std::span<std::uint8_t>,
                               std::span<std::uint8_t>) {
      seen.push_back(view.step);
      if (throw_once && seen.size() == 1) throw std::runtime_error("interrupted");
    };
  };
  Population smooth = Line(3, cell, 5), stopped = Line(3, cell, 5);
  smooth.SetRule(rule(false));
  for (int s = 0; s < 20; ++s) ASSERT_TRUE(smooth.Step());
  seen.clear();
  stopped.SetRule(rule(true));
  for (int s = 0; s < 4; ++s) ASSERT_TRUE(stopped.Step());
  EXPECT_THROW(stopped.Step(), std::runtime_error);
  EXPECT_EQ(stopped.engine().step(), 5);
  EXPECT_EQ(stopped.summary().rule_steps, 0);
  for (int s = 0; s < 15; ++s) ASSERT_TRUE(stopped.Step());
  EXPECT_EQ(seen, (std::vector<std::int64_t>{5, 5, 10, 15, 20}));
  EXPECT_GT(stopped.count(), 3);
  EXPECT_EQ(stopped.count(), smooth.count());
  EXPECT_TRUE(stopped.Positions() == smooth.Positions());
}

// The positions user code reads are gathered once per state: the same storage for every read
// between two steps, the engine's positions, and new ones after a step.
TEST(PopulationUserCode, PositionsAreGatheredOncePerStep) {
  Population p = Line(4, AgentType{}, 1000);
  std::vector<const double*> addresses;
  p.SetDrift([&](const PopulationView& view, std::span<double> v) {
    addresses.push_back(view.positions().data());
    addresses.push_back(view.positions().data());
    v[1] = 1.0;
  });
  ASSERT_TRUE(p.Step());
  ASSERT_EQ(addresses.size(), 2u);
  EXPECT_EQ(addresses[0], addresses[1]);
  const std::span<const double> now = p.CurrentPositions();
  EXPECT_TRUE(std::vector<double>(now.begin(), now.end()) == p.Positions());
  EXPECT_EQ(now[1], 0.01);  // after the step, not the copy the drift read
}

TEST(PopulationUserCode, DriftAndRuleGiveTheSameBitsOnOneAndTwoThreads) {
  AgentType cell;
  cell.radius = 0.5;
  cell.growth_rate = 0.2;
  auto run = [&](int threads) {
    Population p = Line(16, cell, 4, threads, {{"signal", 1.0, Inheritance::kSplit}});
    p.SetDrift([](const PopulationView& view, std::span<double> v) {  // toward the origin
      for (std::size_t i = 0; i < view.agents.size(); ++i) {
        v[2 * i] = -0.3 * view.positions()[2 * i];
        v[2 * i + 1] = -0.3 * view.positions()[2 * i + 1];
      }
    });
    p.SetRule([](PopulationView& view, std::span<std::uint8_t> divide, std::span<std::uint8_t>) {
      for (std::size_t i = 0; i < view.agents.size(); ++i) {
        view.variables[0][i] += view.rule_dt;
        divide[i] = view.variables[0][i] > 1.5 ? 1 : 0;
      }
    });
    for (int s = 0; s < 120; ++s) EXPECT_TRUE(p.Step());
    return p;
  };
  const Population one = run(1), two = run(2);
  EXPECT_GT(one.count(), 16);
  ASSERT_EQ(one.count(), two.count());
  const std::vector<double> a = one.Positions(), b = two.Positions();
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  // The engine's overlap is the exact maximum over all pairs, and the jam toward the origin
  // stays resolved to within a fraction of a radius.
  EXPECT_EQ(one.engine().MaxPairOverlap(),
            BruteForceMaxOverlap(one.engine().model(), one.Positions()));
  EXPECT_LT(one.engine().MaxPairOverlap(), 0.25);
}

}  // namespace
}  // namespace moreau::particles
