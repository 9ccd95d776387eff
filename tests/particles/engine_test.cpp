// The particle engine against the foundation's solver, across thread counts, and its invariants.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "moreau/common/random.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/stepper.h"
#include "moreau/pbd/study.h"
#include "particles/test_util.h"

namespace moreau::particles {
namespace {

using testing::BruteForceMaxOverlap;

// The paper's disks case (moreau::pbd::DisksCase) as an engine model: trap −γx, optional wall.
struct DisksSetup {
  ParticleModel model;
  Forces forces;
  std::vector<double> x0;
};

DisksSetup FromDisksCase(const pbd::DisksCase& c) {
  DisksSetup s;
  s.model.dimension = 2;
  s.model.radius.assign(static_cast<std::size_t>(c.count), c.radius);
  if (c.wall) s.model.walls.push_back(Wall{{0.0, 1.0, 0.0}, *c.wall});
  s.forces.trap = HarmonicTrap{c.gamma, {0.0, 0.0, 0.0}};
  const pbd::Vector x = c.InitialState();
  s.x0.assign(x.data(), x.data() + x.size());
  return s;
}

std::vector<double> RunEngine(const DisksSetup& s, EngineOptions o, double T,
                              const std::function<void(const Engine&)>& after = {}) {
  Engine e(s.model, s.forces, o, s.x0);
  EngineObserver observer;
  if (after) {
    observer = [&](const Engine& engine) {
      if (engine.step() > 0) after(engine);
      return true;
    };
  }
  const EngineSummary summary = e.Run(T, observer);
  EXPECT_TRUE(summary.ok()) << summary.message;
  return e.Positions();
}

pbd::Vector RunFoundation(const pbd::DisksCase& c, double h, double T) {
  pbd::ParticleConstraints constraints(c.MakeModel(), {pbd::PairSearch::kAllPairs, 1.0});
  pbd::StepperOptions o;
  o.h = h;
  o.monitor_violation = false;
  pbd::Vector x;
  const auto summary = pbd::Simulate(*c.MakeDrift(), constraints, o, c.InitialState(), T, {}, &x);
  EXPECT_TRUE(summary.ok());
  return x;
}

TEST(ParticleEngine, LexicographicOrderGivesTheFoundationsBits) {
  // Same sets, same order, same arithmetic as moreau::pbd's all-pairs ParticleConstraints: the
  // engine's Verlet list leaves out only pairs that cannot touch, so the bits agree.
  for (const bool wall : {false, true}) {
    pbd::DisksCase c;  // 40 disks, R = 0.1, γ = 1
    if (wall) c.wall = -0.6;
    const double h = 1.0 / 512;
    const DisksSetup s = FromDisksCase(c);
    EngineOptions o;
    o.h = h;
    o.order = SweepOrder::kLexicographic;
    const std::vector<double> x = RunEngine(s, o, 1.0);
    const pbd::Vector ref = RunFoundation(c, h, 1.0);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(ref.size()));
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_EQ(x[i], ref[static_cast<Eigen::Index>(i)]) << "entry " << i << " wall " << wall;
    }
  }
}

TEST(ParticleEngine, ColouredOrderConvergesToThePngsReference) {
  // The coloured order is a different sweep order, so its trajectory differs from the foundation's
  // by O(h); both converge to the same solution. Reference: the foundation's PNGS at h = 2^−16
  // (reltol 1e−10, abstol 1e−12). Error = max over the time grid of ‖x_k − x(t_k)‖.
  pbd::DisksCase c;
  c.T = 1.0;
  const DisksSetup s = FromDisksCase(c);
  pbd::StudyProblem problem;
  problem.constraints = std::make_shared<pbd::ParticleSystemModel>(
      std::make_shared<const particles::ParticleModel>(c.MakeModel()));
  problem.drift = c.MakeDrift();
  problem.x0 = c.InitialState();
  problem.T = c.T;
  pbd::StepperOptions ref;
  ref.method = pbd::Method::kPNGS;
  ref.h = std::pow(2.0, -16);
  ref.monitor_violation = false;
  const pbd::SampledTrajectory reference = pbd::ComputeReference(problem, ref, std::pow(2.0, -12));
  std::vector<double> hs, errors;
  // h = 2^−9 … 2^−12: at least 16× the reference step (as the foundation's own study keeps).
  for (int k = 9; k <= 12; ++k) {
    const double h = std::pow(2.0, -k);
    EngineOptions o;
    o.h = h;
    o.order = SweepOrder::kColoured;
    o.block_cells = 2;  // several blocks and colours even for 40 disks
    double error = 0.0;
    RunEngine(s, o, c.T, [&](const Engine& e) {
      const std::vector<double> x = e.Positions();
      const pbd::Vector xr = reference.At(e.time());
      double d2 = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i) {
        d2 += (x[i] - xr[static_cast<Eigen::Index>(i)]) * (x[i] - xr[static_cast<Eigen::Index>(i)]);
      }
      error = std::max(error, std::sqrt(d2));
    });
    // The foundation's PBD (lexicographic order) at the same h.
    pbd::StudyProblem p2 = problem;
    p2.solution = [&reference](double t) { return reference.At(t); };
    const auto rows = pbd::RunStudy(p2, {pbd::ParseMethodSpec("pbd")}, {h}, pbd::StepperOptions{});
    hs.push_back(h);
    errors.push_back(error);
    std::printf("[          ] h = 2^-%d: coloured error %.3e, foundation (lexicographic) %.3e\n", k,
                error, rows[0].error);
    EXPECT_LT(error, 2.0 * rows[0].error) << "h = " << h << " foundation " << rows[0].error;
    EXPECT_GT(error, 0.5 * rows[0].error) << "h = " << h << " foundation " << rows[0].error;
  }
  const double order = pbd::ObservedOrder(hs, errors);
  std::printf("[          ] observed order %.3f\n", order);
  EXPECT_NEAR(order, 1.0, 0.2);
}

DisksSetup PeriodicSoup(int n, double phi, std::uint64_t seed) {
  // Polydisperse disks (r ∈ [0.4, 0.6]) in a doubly periodic square at packing fraction ≈ phi.
  DisksSetup s;
  s.model.dimension = 2;
  SplitMix64 rng(seed);
  double area = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = 0.4 + 0.2 * rng.Uniform01();
    s.model.radius.push_back(r);
    area += std::numbers::pi * r * r;
  }
  const double L = std::sqrt(area / phi);
  s.model.periodic = {true, true, false};
  s.model.domain_lo = {-0.5 * L, -0.5 * L, 0.0};
  s.model.domain_hi = {0.5 * L, 0.5 * L, 0.0};
  s.x0 = RandomSequentialAddition(s.model, s.model.domain_lo, s.model.domain_hi, seed);
  return s;
}

TEST(ParticleEngine, BitIdenticalForAnyThreadCount2d) {
  DisksSetup s = PeriodicSoup(1200, 0.45, 11);
  s.forces.diffusion = 0.05;
  s.forces.constant_force = {0.3, -0.1, 0.0};
  s.forces.attraction = PairAttraction{2.0, 0.2, {}};
  s.model.mobility.assign(s.model.radius.size(), 1.0);
  for (std::size_t i = 0; i < s.model.mobility.size(); i += 3) s.model.mobility[i] = 0.5;
  std::vector<std::vector<double>> results;
  std::vector<EngineStats> stats;
  for (int threads : {1, 2, 3}) {
    EngineOptions o;
    o.h = 0.01;
    o.seed = 99;
    o.threads = threads;
    o.block_cells = 3;
    Engine e(s.model, s.forces, o, s.x0);
    const EngineSummary summary = e.Run(40 * o.h);
    ASSERT_TRUE(summary.ok()) << summary.message;
    results.push_back(e.Positions());
    stats.push_back(summary.stats);
  }
  EXPECT_GT(stats[0].neighbour_list_builds, 2);
  EXPECT_GT(stats[0].projections, 100);
  for (std::size_t t = 1; t < results.size(); ++t) {
    EXPECT_TRUE(results[t] == results[0]) << "thread count #" << t;
    EXPECT_EQ(stats[t].neighbour_list_builds, stats[0].neighbour_list_builds);
    EXPECT_EQ(stats[t].projections, stats[0].projections);
    EXPECT_EQ(stats[t].max_overlap, stats[0].max_overlap);
  }
}

// TakeActiveVelocities (one pass: the sum, the storage order, the check, the zeroing) against
// SetActiveVelocities of the sum, in 2 and 3 dimensions on two threads, on a storage order that is
// not the id order; then the lowest id of the non-finite ones, and a sum of huge finite values that
// is no failure.
TEST(ParticleEngine, TakenActiveVelocitiesEqualTheCopiedSumAndNameTheLowestBadId) {
  for (int k : {2, 3}) {
    ParticleModel model;
    model.dimension = k;
    const int n = k == 2 ? 20000 : 300;  // 2-D: enough for the gather on two threads
    const double side = k == 2 ? 100.0 : 10.0;
    model.radius.assign(n, 0.1);
    SplitMix64 rng(static_cast<std::uint64_t>(7 + k));
    std::vector<double> x, v, m;
    for (int j = 0; j < k * n; ++j) {
      x.push_back(side * rng.Uniform01());
      v.push_back(rng.Uniform01() - 0.5);
      m.push_back(0.1 * (rng.Uniform01() - 0.5));
    }
    EngineOptions o;
    o.h = 0.01;
    o.check_initial_state = false;
    o.threads = 2;
    Engine taken(model, Forces{}, o, x), copied(model, Forces{}, o, x);
    ASSERT_NE(taken.Stored().ids[0], 0) << "the storage order should differ from the ids";
    std::vector<double> sum(v.size()), buffer = v;
    for (std::size_t j = 0; j < v.size(); ++j) sum[j] = v[j] + m[j];
    EXPECT_EQ(taken.TakeActiveVelocities(buffer, m), -1);
    EXPECT_EQ(buffer, std::vector<double>(v.size(), 0.0));
    copied.SetActiveVelocities(sum);
    ASSERT_TRUE(taken.Step() && copied.Step());
    EXPECT_TRUE(taken.Positions() == copied.Positions()) << k;
    buffer.assign(v.size(), 1e308);  // the fast check's sum overflows; every value is finite
    EXPECT_EQ(taken.TakeActiveVelocities(buffer), -1);
    buffer[static_cast<std::size_t>(k * 41)] = std::nan("");
    buffer[static_cast<std::size_t>(k * 17 + k - 1)] = -std::numeric_limits<double>::infinity();
    EXPECT_EQ(taken.TakeActiveVelocities(buffer), 17);
  }
}

// A redo (a step whose sweeps moved particles past half the skin, redone with a list built at
// its predicted positions) predicts again from the step's start: every particle from its own
// position, though the build before the redo reordered the storage. Noise of 0.1 per step against
// a skin of 0.01 makes every step build and many redo; a particle then moves less than 2 r_max per
// step (a prediction from another particle's slot would move it about L/4 ≈ 10), and the bits are
// the same on 1 and 2 threads.
TEST(ParticleEngine, RedoPredictsEachParticleFromItsOwnPosition) {
  DisksSetup s = PeriodicSoup(1200, 0.5, 21);
  s.forces.diffusion = 0.5;
  const double L = s.model.domain_hi[0] - s.model.domain_lo[0];
  std::vector<std::vector<double>> results;
  for (const int threads : {1, 2}) {
    EngineOptions o;
    o.h = 0.01;
    o.seed = 5;
    o.threads = threads;
    o.skin_factor = 0.02;
    Engine e(s.model, s.forces, o, s.x0);
    std::vector<double> before = e.Positions();
    double largest = 0.0;
    for (int step = 0; step < 20; ++step) {
      ASSERT_TRUE(e.Step()) << e.summary().message;
      const std::vector<double> after = e.Positions();
      for (std::size_t i = 0; i < after.size() / 2; ++i) {
        double d2 = 0.0;
        for (std::size_t a = 0; a < 2; ++a) {
          const double u = after[2 * i + a] - before[2 * i + a];
          const double image = u - L * std::round(u / L);
          d2 += image * image;
        }
        largest = std::max(largest, std::sqrt(d2));
      }
      before = after;
    }
    EXPECT_GT(e.summary().stats.verlet_retries, 0);
    EXPECT_LT(largest, 2.0 * 0.6) << "threads " << threads;
    results.push_back(e.Positions());
  }
  EXPECT_TRUE(results[0] == results[1]);
}

TEST(ParticleEngine, BitIdenticalForAnyThreadCount3dWithObstacles) {
  ParticleModel m;
  m.dimension = 3;
  SplitMix64 rng(5);
  for (int i = 0; i < 800; ++i) m.radius.push_back(0.3 + 0.2 * rng.Uniform01());
  m.AddBoxWalls({0, 0, 0}, {12, 12, 12});
  m.spheres.push_back({{6, 6, 3}, 1.5});
  m.periodic = {true, false, false};
  m.domain_lo = {0, 0, 0};
  m.domain_hi = {12, 12, 12};
  m.walls.erase(m.walls.begin(), m.walls.begin() + 2);  // x is periodic: no walls there
  const std::vector<double> x0 = RandomSequentialAddition(m, {0, 0, 0}, {12, 12, 12}, 3);
  Forces f;
  f.constant_force = {0.0, 0.0, -2.0};  // settle onto the floor and the sphere
  f.diffusion = 0.02;
  std::vector<std::vector<double>> results;
  for (int threads : {1, 2}) {
    EngineOptions o;
    o.h = 0.01;
    o.threads = threads;
    o.block_cells = 2;
    Engine e(m, f, o, x0);
    const EngineSummary summary = e.Run(40 * o.h);
    ASSERT_TRUE(summary.ok()) << summary.message;
    EXPECT_LT(e.MaxViolation(), 0.5);
    results.push_back(e.Positions());
  }
  EXPECT_TRUE(results[0] == results[1]);
}

TEST(ParticleEngine, PaperDisksOverlapStaysBelowKhInTheColouredOrder) {
  // Bounded constraint violation (paper 000, Def. 2.8) for the paper's 40 disks in the coloured
  // order: after every step the largest overlap over all pairs is below K h with the foundation's
  // K = 4 (it measures ≤ 3.6 in the lexicographic order), h = 2^−3 … 2^−10.
  constexpr double kK = 4.0;
  pbd::DisksCase c;
  c.T = 1.0;
  const DisksSetup s = FromDisksCase(c);
  for (int k = 3; k <= 10; ++k) {
    EngineOptions o;
    o.h = std::pow(2.0, -k);
    o.block_cells = 2;
    double worst = 0.0;
    RunEngine(s, o, c.T, [&](const Engine& e) {
      worst = std::max(worst, BruteForceMaxOverlap(s.model, e.Positions()));
      EXPECT_EQ(e.summary().stats.last_overlap, e.MaxPairOverlap());
    });
    EXPECT_LT(worst, kK * o.h) << "h = 2^-" << k;
    EXPECT_GT(worst, 0.0);
  }
}

TEST(ParticleEngine, NonFiniteDriftStopsNamingStepAndParticle) {
  ParticleModel m;
  m.radius = {0.1, 0.1, 0.1};
  const std::vector<double> x0 = {0.0, 0.0, 1.0, 0.0, 1e306, 0.0};
  Forces f;
  f.trap = HarmonicTrap{1e3, {0, 0, 0}};
  EngineOptions o;
  o.h = 1.0;
  Engine e(m, f, o, x0);
  EXPECT_FALSE(e.Step());
  const EngineSummary s = e.summary();
  EXPECT_EQ(s.termination, Termination::kNonFinite);
  EXPECT_EQ(s.failed_step, 1);
  EXPECT_EQ(s.failed_particle, 2);
  EXPECT_NE(s.message.find("particle 2"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("step 1"), std::string::npos) << s.message;
  EXPECT_TRUE(e.Positions() == x0);  // the last good state
  EXPECT_FALSE(e.Step());
}

TEST(ParticleEngine, FixOverlapsProjectsToAFeasibleState) {
  ParticleModel m;
  SplitMix64 rng(4);
  std::vector<double> x;
  for (int i = 0; i < 400; ++i) {
    m.radius.push_back(0.5);
    x.push_back(20.0 * rng.Uniform01());
    x.push_back(20.0 * rng.Uniform01());
  }
  m.AddBoxWalls({-1, -1, 0}, {21, 21, 0});
  EXPECT_THROW(CheckInitialState(m, x), InputError);
  const int sweeps = FixOverlaps(m, x);
  EXPECT_GT(sweeps, 0);
  EXPECT_NO_THROW(CheckInitialState(m, x));
  EXPECT_LE(BruteForceMaxOverlap(m, x), 1e-10 * 0.5);
  EXPECT_EQ(FixOverlaps(m, x), 0);
}

TEST(ParticleEngine, CrowdLeavesARoomThroughTheDoor) {
  // A Maury–Venel-type evacuation: 150 people (disks) head for a point beyond the door at speed
  // v0 = 1 and leave the room [0, 10]² through a door of width 1.2 in its right wall; the walls
  // and door posts are segments. A dense run: the jam at the door. One PBD sweep per step leaves
  // overlaps of O(h) whose constant grows with the depth of the jam: over 25 s we measured max
  // overlap / h ≈ 17–18 at h = 0.01 and 20–22 at h = 0.005 (the spread: sweep orders of different
  // skins and block sizes; wall violations likewise), and state
  // K = 30 for this scenario.
  constexpr double kK = 30.0;
  ParticleModel m;
  SplitMix64 rng(2);
  for (int i = 0; i < 150; ++i) m.radius.push_back(0.2 + 0.05 * rng.Uniform01());
  m.segments = {{{0, 0}, {10, 0}},
                {{0, 10}, {10, 10}},
                {{0, 0}, {0, 10}},
                {{10, 0}, {10, 4.4}},
                {{10, 5.6}, {10, 10}}};
  const std::vector<double> x0 = RandomSequentialAddition(m, {0.3, 0.3, 0}, {9.7, 9.7, 0}, 1);
  Forces f;
  f.propulsion =
      SelfPropulsion{1.0, {13.0, 5.0, 0.0}, std::nullopt, std::nullopt, std::nullopt, nullptr};
  for (const double h : {0.01, 0.005}) {
    EngineOptions o;
    o.h = h;
    Engine e(m, f, o, x0);
    double worst = 0.0;
    int out = 0;
    for (int step = 0; step < std::lround(25.0 / h); ++step) {
      ASSERT_TRUE(e.Step());
      worst = std::max(worst, e.MaxViolation());
    }
    const std::vector<double> x = e.Positions();
    for (int i = 0; i < m.count(); ++i) out += x[static_cast<std::size_t>(2 * i)] > 10.0 ? 1 : 0;
    EXPECT_GT(out, 90) << "h = " << h;  // most have left
    const double overlap = e.summary().stats.max_overlap;
    EXPECT_LT(overlap, kK * h);
    EXPECT_LT(worst, kK * h);
    EXPECT_GT(overlap, 0.0);
    std::printf(
        "[          ] crowd h = %g: out %d, max overlap / h = %.2f, max violation / h = %.2f\n", h,
        out, overlap / h, worst / h);
  }
}

TEST(ParticleEngine, MoreSweepsShrinkTheOverlapsAndStayDeterministic) {
  // A jam: 120 disks pushed into a corner of a box. sweeps = s repeats the sweep s times per step
  // (PNGS truncated at s); the overlap must shrink with s, and stay the same bits for any thread
  // count. The exit direction takes a disk past the target straight on.
  ParticleModel m;
  m.radius.assign(120, 0.25);
  m.AddBoxWalls({0, 0, 0}, {8, 8, 0});
  const std::vector<double> x0 = RandomSequentialAddition(m, {0, 0, 0}, {8, 8, 0}, 5);
  Forces f;
  f.propulsion =
      SelfPropulsion{1.0, {0.0, 0.0, 0.0}, std::nullopt, std::nullopt, std::nullopt, nullptr};
  double previous = std::numeric_limits<double>::infinity();
  for (const int sweeps : {1, 4, 16}) {
    EngineOptions o;
    o.h = 0.01;
    o.sweeps = sweeps;
    std::vector<double> x_one;
    for (const int threads : {1, 2}) {
      o.threads = threads;
      Engine e(m, f, o, x0);
      e.Run(800 * o.h);
      if (threads == 1) {
        x_one = e.Positions();
        const double overlap = e.summary().stats.max_overlap;
        EXPECT_LT(overlap, 0.7 * previous) << "sweeps = " << sweeps;
        previous = overlap;
        EXPECT_EQ(e.summary().stats.constraint_evaluations % sweeps, 0);
      } else {
        EXPECT_EQ(e.Positions(), x_one) << "sweeps = " << sweeps;
      }
    }
  }
  EngineOptions bad;
  bad.sweeps = 0;
  EXPECT_THROW(bad.Validate(), InputError);

  // Exit direction: past the target line x = 1 (⟨X − (1, 0), e_1⟩ > 0) a free disk walks along
  // +e_1 at v0 instead of turning back to the target.
  ParticleModel one;
  one.radius = {0.1};
  Forces g;
  g.propulsion = SelfPropulsion{
      2.0, {1.0, 0.0, 0.0}, Vec3{1.0, 1.0, 0.0}, Vec3{1.0, 0.0, 0.0}, std::nullopt, nullptr};
  EngineOptions o;
  o.h = 0.01;
  Engine e(one, g, o, std::vector<double>{1.5, 0.5});
  e.Run(10 * o.h);
  const std::vector<double> x = e.Positions();
  EXPECT_NEAR(x[0], 1.5 + 10 * 0.01 * 2.0, 1e-12);
  EXPECT_NEAR(x[1], 0.5, 1e-12);
}

}  // namespace
}  // namespace moreau::particles
