// Population checkpoints: a population stopped at some step (between rule steps or right after
// one), saved through a checkpoint file, restored into a fresh population (another thread count)
// and continued gives the same bits as the population that never stopped: agents, user
// variables, positions, counters. States that do not fit are refused.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "moreau/particles/checkpoint.h"
#include "moreau/particles/population.h"
#include "particles/population_test_util.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::Colony;
using testing::ExpectInputError;
using testing::GrowingColony;
using testing::Make;
using testing::SameBits;

// GrowingColony with 24 agents in a periodic box, division at a rate too, faster death, alignment
// with the velocity, contact inhibition for one type, a user variable split at divisions and
// relaxation after every rule step.
Colony MixedCheckpointColony() {
  Colony c = GrowingColony();
  c.geometry.periodic = {true, true, false};
  c.geometry.domain_lo = {0, 0, 0};
  c.geometry.domain_hi = {16, 16, 0};
  for (AgentType& t : c.rules.types) {
    t.division_rate = 0.2;
    t.death_rate = 0.05;
    t.speed = 0.2;
    t.velocity_alignment = 0.5;
  }
  c.rules.types[1].max_contacts = 4;
  c.rules.variables = {{"amount", 1.0, Inheritance::kSplit}};
  c.rules.relax = true;
  c.types.clear();
  c.x0.clear();
  for (int i = 0; i < 24; ++i) {
    c.types.push_back(i % 2);
    c.x0.push_back(2.0 + 2.5 * (i % 6));
    c.x0.push_back(2.0 + 2.5 * (i / 6));
  }
  return c;
}

Population MakeOn(Colony c, int threads) {
  c.options.threads = threads;
  return Make(c);
}

void ExpectSamePopulation(const Population& a, const Population& b) {
  ASSERT_EQ(a.count(), b.count());
  for (std::size_t i = 0; i < a.agents().size(); ++i) {
    const Agent &x = a.agents()[i], &y = b.agents()[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.generation, y.generation);
    EXPECT_EQ(x.divisions, y.divisions);
    EXPECT_EQ(x.mother, y.mother);
    EXPECT_EQ(std::memcmp(&x.radius, &y.radius, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&x.age, &y.age, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(x.polarity.data(), y.polarity.data(), sizeof(x.polarity)), 0);
  }
  const std::span<const double> va = a.variable(0), vb = b.variable(0);
  EXPECT_TRUE(SameBits({va.begin(), va.end()}, {vb.begin(), vb.end()}));
  EXPECT_TRUE(SameBits(a.Positions(), b.Positions()));
  const PopulationSummary sa = a.summary(), sb = b.summary();
  EXPECT_EQ(sa.rule_steps, sb.rule_steps);
  EXPECT_EQ(sa.births, sb.births);
  EXPECT_EQ(sa.deaths, sb.deaths);
  EXPECT_EQ(sa.relax_sweeps, sb.relax_sweeps);
  EXPECT_EQ(sa.max_overlap_before, sb.max_overlap_before);
  EXPECT_EQ(sa.engine.stats.projections, sb.engine.stats.projections);
  EXPECT_EQ(sa.engine.stats.neighbour_list_builds, sb.engine.stats.neighbour_list_builds);
  EXPECT_EQ(a.last_deaths(), b.last_deaths());
}

// `stop` steps, a save through a checkpoint file, a restore into a fresh population with
// `resume_threads`, the rest up to `total`; against `total` steps uninterrupted.
void ExpectPopulationResumeBitIdentical(int stop, int total, int threads, int resume_threads) {
  const Colony c = MixedCheckpointColony();
  const double h = c.options.h;
  Population whole = MakeOn(c, threads);
  whole.Run(total * h);
  ASSERT_GT(whole.summary().births, 10);  // the roster changed many times
  ASSERT_GT(whole.summary().deaths, 0);

  Population first = MakeOn(c, threads);
  first.Run(stop * h);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("moreau_population_checkpoint_" + std::to_string(stop) + ".bin");
  const PopulationState saved = first.SaveState();
  WriteCheckpoint(file, saved.engine, {{"population", saved.ToJson()}});
  nlohmann::json run;
  const EngineState engine = ReadCheckpoint(file, &run);
  std::filesystem::remove(file);

  Population resumed = MakeOn(c, resume_threads);
  resumed.RestoreState(PopulationState::FromJson(run.at("population"), engine));
  ExpectSamePopulation(first, resumed);
  int rule_steps = 0;
  resumed.Continue(total * h, [&](const Population&) { return ++rule_steps > 0; });
  EXPECT_EQ(rule_steps, total / c.rules.interval - stop / c.rules.interval);
  EXPECT_EQ(resumed.engine().step(), total);
  ExpectSamePopulation(whole, resumed);
}

TEST(PopulationCheckpoint, ResumeBetweenRuleStepsIsBitIdentical) {
  ExpectPopulationResumeBitIdentical(/*stop=*/203, /*total=*/400, /*threads=*/1,
                                     /*resume_threads=*/2);
}

TEST(PopulationCheckpoint, ResumeRightAfterARuleStepIsBitIdentical) {
  ExpectPopulationResumeBitIdentical(/*stop=*/250, /*total=*/400, /*threads=*/2,
                                     /*resume_threads=*/1);
}

TEST(PopulationCheckpoint, StatesThatDoNotFitAreRefused) {
  const Colony c = MixedCheckpointColony();
  Population p = MakeOn(c, 1);
  p.Run(100 * c.options.h);
  const PopulationState good = p.SaveState();
  {
    PopulationState s = good;
    s.variables.clear();
    ExpectInputError([&] { MakeOn(c, 1).RestoreState(s); }, "user variables");
  }
  {
    PopulationState s = good;
    s.agents.front().type = 7;
    ExpectInputError([&] { MakeOn(c, 1).RestoreState(s); }, "bad type");
  }
  {
    PopulationState s = good;
    s.agents.pop_back();
    ExpectInputError([&] { MakeOn(c, 1).RestoreState(s); }, "agents but an engine");
  }
  nlohmann::json j = good.ToJson();
  j["agents"]["radius"].erase(0);
  ExpectInputError([&] { (void)PopulationState::FromJson(j, good.engine); }, "differ in length");
  j = good.ToJson();
  j.erase("counters");
  ExpectInputError([&] { (void)PopulationState::FromJson(j, good.engine); }, "counters");
}

}  // namespace
}  // namespace moreau::particles
