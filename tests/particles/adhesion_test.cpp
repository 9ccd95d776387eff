// Differential adhesion: the pair attraction with a stiffness per pair of adhesion classes
// (forces.h PairAttraction::class_stiffness, model.h adhesion_class) and per pair of agent types
// (population.h PopulationRules::adhesion), and the segregation index.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "moreau/particles/engine.h"
#include "moreau/particles/initial_state.h"
#include "moreau/particles/population.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::ExpectInputError;

// Three types a, b, c of radius 0.5 with a stiffness for every pair; range ℓ = 0.3.
PopulationRules ThreeTypes() {
  PopulationRules r;
  for (const char* name : {"a", "b", "c"}) {
    AgentType t;
    t.name = name;
    r.types.push_back(t);
  }
  r.interval = 1000;  // no rule step in these runs
  r.adhesion = {{{"a", "a"}, 3.0}, {{"a", "b"}, 0.7}, {{"c", "b"}, 0.2}, {{"b", "b"}, 1.1}};
  return r;  // (a, c) and (c, c) are not given: the uniform stiffness
}

// Two agents of types (ta, tb) with a surface gap g in (0, ℓ), no noise: after one step each has
// moved by h μ k_ab g (1 − g/ℓ) toward the other (the closed form of the uniform case, forces.h),
// k_ab from the matrix, the uniform stiffness for the pairs the rules do not name.
TEST(Adhesion, TwoAgentsOfTypesABAttractWithTheirPairsStiffness) {
  const double h = 0.01, range = 0.3, g = 0.1, uniform = 0.45;
  const std::vector<std::pair<std::pair<int, int>, double>> cases = {
      {{0, 0}, 3.0}, {{0, 1}, 0.7}, {{1, 0}, 0.7},     {{1, 1}, 1.1},
      {{1, 2}, 0.2}, {{2, 1}, 0.2}, {{0, 2}, uniform}, {{2, 2}, uniform}};
  for (const auto& [pair, k] : cases) {
    ParticleModel geometry;
    geometry.dimension = 2;
    Forces forces;
    forces.attraction = PairAttraction{uniform, range, {}};
    EngineOptions options;
    options.h = h;
    const std::vector<int> types = {pair.first, pair.second};
    const std::vector<double> x0 = {0.0, 0.0, 1.0 + g, 0.0};
    Population p(geometry, forces, options, ThreeTypes(), types, x0);
    ASSERT_TRUE(p.Step());
    const std::vector<double> x = p.Positions();
    const double move = h * k * g * (1.0 - g / range);
    EXPECT_NEAR(x[0], move, 1e-15) << pair.first << "," << pair.second;
    EXPECT_NEAR(x[2], 1.0 + g - move, 1e-15) << pair.first << "," << pair.second;
    EXPECT_EQ(x[1], 0.0);
    EXPECT_EQ(x[3], 0.0);
  }
}

// A periodic soup of n disks of radius 0.5 (RSA) with noise and attraction, classes 0, 1, 0, …
struct Soup {
  ParticleModel model;
  Forces forces;
  std::vector<double> x0;
};

Soup AttractiveSoup(int n, std::uint64_t seed) {
  Soup s;
  s.model.dimension = 2;
  s.model.radius.assign(static_cast<std::size_t>(n), 0.5);
  const double L = std::sqrt(n * 0.7854 / 0.45);
  s.model.periodic = {true, true, false};
  s.model.domain_lo = {0.0, 0.0, 0.0};
  s.model.domain_hi = {L, L, 0.0};
  for (int i = 0; i < n; ++i) s.model.adhesion_class.push_back(i % 2);
  s.forces.diffusion = 0.02;
  s.forces.attraction = PairAttraction{2.0, 0.2, {}};
  s.x0 = RandomSequentialAddition(s.model, s.model.domain_lo, s.model.domain_hi, seed);
  return s;
}

std::vector<double> RunSoup(const Soup& s, int threads, int steps) {
  EngineOptions o;
  o.h = 0.01;
  o.seed = 7;
  o.threads = threads;
  o.block_cells = 3;
  Engine e(s.model, s.forces, o, s.x0);
  for (int i = 0; i < steps; ++i) EXPECT_TRUE(e.Step());
  return e.Positions();
}

TEST(Adhesion, MatrixOfEqualEntriesGivesTheBitsOfTheUniformStiffness) {
  Soup s = AttractiveSoup(600, 3);
  const std::vector<double> uniform = RunSoup(s, 2, 40);
  s.forces.attraction->class_stiffness.assign(4, 2.0);
  s.forces.attraction->stiffness = 0.0;  // the matrix replaces it
  EXPECT_TRUE(RunSoup(s, 2, 40) == uniform);
  s.forces.attraction->class_stiffness = {2.0, 1.0, 1.0, 0.5};
  EXPECT_FALSE(RunSoup(s, 2, 40) == uniform);  // a matrix with other entries moves them
}

TEST(Adhesion, DifferentialAdhesionIsBitIdenticalOnOneAndTwoThreads) {
  Soup s = AttractiveSoup(600, 5);
  s.forces.attraction->class_stiffness = {4.0, 1.0, 1.0, 0.5};
  const std::vector<double> one = RunSoup(s, 1, 60);
  EXPECT_TRUE(RunSoup(s, 2, 60) == one);
  // The same through a population: types, adhesion by name, the segregation index.
  PopulationRules rules = ThreeTypes();
  rules.interval = 10;
  rules.contact_factor = 1.2;
  std::vector<int> types;
  for (int i = 0; i < s.model.count(); ++i) types.push_back(i % 3);
  std::vector<std::vector<double>> x;
  std::vector<double> segregation;
  for (int threads : {1, 2}) {
    EngineOptions o;
    o.h = 0.01;
    o.threads = threads;
    o.block_cells = 3;
    ParticleModel geometry = s.model;
    geometry.adhesion_class.clear();
    Population p(geometry, s.forces, o, rules, types, s.x0);
    EXPECT_TRUE(p.Run(0.6).ok());
    x.push_back(p.Positions());
    segregation.push_back(p.Observe().segregation);
  }
  EXPECT_TRUE(x[1] == x[0]);
  EXPECT_EQ(segregation[1], segregation[0]);
  EXPECT_GT(segregation[0], 0.0);
}

TEST(Adhesion, SegregationIndexOfSmallConfigurations) {
  const std::vector<int> types = {0, 0, 1, 1};
  using Pairs = std::vector<std::pair<int, int>>;
  EXPECT_EQ(SegregationIndex(types, Pairs{{0, 1}, {2, 3}}), 1.0);  // sorted
  EXPECT_EQ(SegregationIndex(types, Pairs{{0, 2}, {1, 3}}), 0.0);  // every contact mixed
  // A chain 0–1–2–3: agents 0 and 3 see their own type only, 1 and 2 one of two.
  EXPECT_EQ(SegregationIndex(types, Pairs{{0, 1}, {1, 2}, {2, 3}}), 0.75);
  // Agent 3 touches nobody and is left out: (1 + 1/2 + 0) / 3.
  EXPECT_DOUBLE_EQ(SegregationIndex(types, Pairs{{0, 1}, {1, 2}}), 0.5);
  EXPECT_EQ(SegregationIndex(types, Pairs{}), 0.0);
}

TEST(Adhesion, BadMatrixOrPairsNameTheKey) {
  Forces f;
  f.attraction = PairAttraction{0.0, 0.2, {1.0, 0.5, 0.5}};
  ExpectInputError([&] { f.Validate(); }, "class_stiffness has 3 entries: it must be C × C");
  f.attraction->class_stiffness = {1.0, 0.5, 0.2, 1.0};
  ExpectInputError([&] { f.Validate(); },
                   "class_stiffness[0][1] (0.5) must equal [1][0] (0.2): the matrix must be "
                   "symmetric");
  f.attraction->class_stiffness = {1.0, 0.5, 0.5, -1.0};
  ExpectInputError([&] { f.Validate(); }, "class_stiffness[1][1] must be ≥ 0 and finite");
  f.attraction->class_stiffness = {std::numeric_limits<double>::infinity()};
  ExpectInputError([&] { f.Validate(); }, "class_stiffness[0][0] must be ≥ 0 and finite");
  f.attraction = PairAttraction{0.0, 0.0, {1.0}};
  ExpectInputError([&] { f.Validate(); }, "forces.attraction.range must be > 0");
  f.attraction = PairAttraction{0.0, 0.2, {1.0, 0.5, 0.5, 1.0}};
  ParticleModel m;
  m.radius = {0.5, 0.5};
  m.adhesion_class = {0, 2};
  ExpectInputError(
      [&] {
        Engine(m, f, EngineOptions{}, std::vector<double>{0, 0, 2, 0});
      },
      "adhesion class of particle 1 is 2, but forces.attraction.class_stiffness has "
      "2 classes");
  m.adhesion_class = {0, -1};
  ExpectInputError([&] { m.Validate(); }, "adhesion class of particle 1 must be ≥ 0 (got -1)");

  PopulationRules r = ThreeTypes();
  r.adhesion[{"a", "d"}] = 1.0;
  ExpectInputError([&] { r.Validate(); }, "adhesion.a.d: unknown type 'd' (types: a, b, c)");
  r.adhesion.erase({"a", "d"});
  r.adhesion[{"b", "c"}] = 0.3;
  ExpectInputError([&] { r.Validate(); },
                   "adhesion.b.c: (0.3) differs from adhesion.c.b (0.2): a pair has one adhesion");
  r.adhesion[{"b", "c"}] = 0.2;  // the same value twice is the same pair
  r.Validate();
  r.adhesion[{"a", "a"}] = -2.0;
  ExpectInputError([&] { r.Validate(); }, "adhesion.a.a: must be ≥ 0 and finite (got -2)");
  r.adhesion[{"a", "a"}] = 1.0;
  ExpectInputError([&] { (void)r.WithAdhesion(Forces{}); },
                   "adhesion: needs the attraction's range ℓ > 0 (forces.attraction_range)");
}

}  // namespace
}  // namespace moreau::particles
