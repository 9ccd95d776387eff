// Validation of the model and data (bad input names its key), the sampled reference, the
// dynamics and the continuation bookkeeping.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "control/random_network.h"
#include "moreau/common/error.h"
#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/refinement_study.h"
#include "moreau/control/spring_network.h"

namespace moreau::control {
namespace {

NetworkNode Free(double x, double y, double mass = 1.0) {
  NetworkNode n;
  n.mass = mass;
  n.position = Eigen::Vector3d(x, y, 0);
  return n;
}
NetworkNode Fixed(double x, double y) {
  NetworkNode n;
  n.fixed = true;
  n.position = Eigen::Vector3d(x, y, 0);
  return n;
}
NetworkSpring Spring(int a, int b, double lo = 0.5, double hi = 1.5) {
  return NetworkSpring{a, b, 1.0, 0.1, lo, hi};
}

// Runs `f`, expecting an InputError whose message contains every string of `parts`.
template <typename F>
void ExpectInputError(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& p : parts) EXPECT_NE(what.find(p), std::string::npos) << what;
  }
}

TEST(ControlSpringNetwork, AcceptsAValidNetwork) {
  SpringNetwork net(2, {Fixed(0, 0), Free(1, 0), Free(1, 1, 2.0)},
                    {Spring(0, 1), Spring(1, 2), Spring(0, 2, 1.0, 2.0)});
  EXPECT_EQ(net.num_free(), 2);
  EXPECT_EQ(net.state_size(), 8);
  EXPECT_EQ(net.free_index(0), -1);
  EXPECT_EQ(net.free_index(2), 1);
  EXPECT_EQ(net.free_node(1), 2);
  EXPECT_EQ(net.MaxRestLength(), 2.0);
  EXPECT_EQ(net.MinRestLength(), 0.5);
}

TEST(ControlSpringNetwork, RejectsBadInputNamingTheKey) {
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Free(1, 0), Free(3, 0)}, {Spring(0, 1)});
      },
      {"network.springs", "disconnected", "node 2"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Fixed(0, 1), Free(1, 0)}, {Spring(0, 1), Spring(0, 2)});
      },
      {"network.springs[0].nodes", "two fixed nodes"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Free(1, 0)}, {Spring(0, 1, 1.5, 0.5)});
      },
      {"network.springs[0].rest_max", "L- = 1.5 exceeds L+ = 0.5"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Free(1, 0, 0.0)}, {Spring(0, 1)});
      },
      {"network.nodes[1].mass", "positive"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Free(1, 0, -2.0)}, {Spring(0, 1)});
      },
      {"network.nodes[1].mass"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Free(1, 1), Free(1, 1)}, {Spring(0, 1)});
      },
      {"network.springs[0].nodes", "coincide"});
  ExpectInputError(
      [] {
        SpringNetwork(4, {Fixed(0, 0), Free(1, 0)}, {Spring(0, 1)});
      },
      {"network.dimension"});
  ExpectInputError(
      [] {
        SpringNetwork(2, {Fixed(0, 0), Free(1, 0)}, {Spring(0, 5)});
      },
      {"network.springs[0].nodes", "out of range"});
  ExpectInputError([] { SpringNetwork(2, {Fixed(0, 0), Fixed(1, 0)}, {}); }, {"network.nodes"});
}

TEST(ControlTrackingProblem, RejectsBadInputNamingTheKey) {
  SpringNetwork net(1, {Fixed(0, 0), Free(1, 0)}, {Spring(0, 1)});
  auto ref = [](double, double* x, double* v, double* w) {
    x[0] = 1;
    v[0] = 0;
    w[0] = 1;
  };
  ExpectInputError([&] { TrackingProblem(net, 0.0, ref, {}, 1e-3); }, {"problem.horizon"});
  ExpectInputError([&] { TrackingProblem(net, 1.0, ref, {}, 0.0); }, {"regularization.gamma"});
  CostWeights w;
  w.velocity = -1;
  ExpectInputError([&] { TrackingProblem(net, 1.0, ref, w, 1e-3); }, {"cost.velocity"});
  const TrackingProblem ok(net, 1.0, ref, {}, 1e-3);
  ExpectInputError([&] { PontryaginDiscretization(ok, 0); }, {"discretization.steps"});
}

TEST(ControlSampledReference, ValidatesShapesAndInterpolates) {
  SpringNetwork net(2, {Fixed(0, 0), Free(1, 0), Free(0, 1)}, {Spring(0, 1), Spring(0, 2)});
  Eigen::MatrixXd pos(3, 4);
  pos << 1, 0, 0, 1,  //
      2, 0, 0, 2,     //
      3, 0, 0, 3;
  ExpectInputError([&] { SampledReference(net, 2.0, pos.leftCols(3), {}, {}, "reference"); },
                   {"reference.positions", "wrong", "4"});
  ExpectInputError(
      [&] { SampledReference(net, 2.0, pos, Eigen::MatrixXd::Zero(2, 4), {}, "reference"); },
      {"reference.velocities"});
  ExpectInputError(
      [&] { SampledReference(net, 2.0, pos, {}, Eigen::MatrixXd::Ones(3, 3), "reference"); },
      {"reference.weights"});
  Eigen::MatrixXd weights(3, 2);
  weights << 1, 1,  //
      0, 1,         //
      1, 1;
  const ReferenceFunction f = SampledReference(net, 2.0, pos, {}, weights, "reference");
  double x[4], v[4], w[2];
  f(0.5, x, v, w);
  EXPECT_DOUBLE_EQ(x[0], 1.5);
  EXPECT_DOUBLE_EQ(x[3], 1.5);
  EXPECT_EQ(w[0], 0.0);  // between a frame with data and one without: no data
  EXPECT_EQ(w[1], 1.0);
  f(1.0, x, v, w);
  EXPECT_EQ(w[0], 0.0);  // on the frame without data
  f(2.0, x, v, w);
  EXPECT_DOUBLE_EQ(x[0], 3.0);
  EXPECT_EQ(w[0], 1.0);
}

TEST(ControlDynamics, ForceIsAlongTheSpringAndVanishesAtRest) {
  // One free node at (3, 4) on a spring to the origin: rest length 5 means no force; a longer
  // rest length pushes the node outward along (3, 4)/5, damping resists the radial velocity.
  NetworkNode mass = Free(3, 4, 2.0);
  SpringNetwork net(2, {Fixed(0, 0), mass}, {NetworkSpring{0, 1, 10.0, 3.0, 1.0, 9.0}});
  Eigen::VectorXd z(4), rate;
  z << 3, 4, 0, 0;
  EvaluateDynamics(net, 0.0, z, Eigen::VectorXd::Constant(1, 5.0), rate);
  EXPECT_NEAR(rate.norm(), 0.0, 1e-14);
  EvaluateDynamics(net, 0.0, z, Eigen::VectorXd::Constant(1, 6.0), rate);
  EXPECT_NEAR(rate[2], 10.0 * 1.0 * 0.6 / 2.0, 1e-14);
  EXPECT_NEAR(rate[3], 10.0 * 1.0 * 0.8 / 2.0, 1e-14);
  z << 3, 4, 0.6, 0.8;  // unit radial velocity
  EvaluateDynamics(net, 0.0, z, Eigen::VectorXd::Constant(1, 5.0), rate);
  EXPECT_NEAR(rate[0], 0.6, 1e-15);
  EXPECT_NEAR(rate[2], -3.0 * 0.6 / 2.0, 1e-14);
  EXPECT_NEAR(rate[3], -3.0 * 0.8 / 2.0, 1e-14);
}

TEST(ControlDynamics, PrescribedMotionOfAFixedNode) {
  // A fixed node moving as p + w t through `motion` gives the same dynamics as through (p, w);
  // a free node cannot have a motion; the coincidence check uses the motion at t = 0.
  NetworkNode anchor = Fixed(0.5, -0.2);
  anchor.velocity = Eigen::Vector3d(0.3, -0.1, 0.0);
  NetworkNode moving = Fixed(99, 99);  // position ignored: the motion decides
  moving.motion = [](double t, double* x, double* v) {
    x[0] = 0.5 + 0.3 * t;
    x[1] = -0.2 - 0.1 * t;
    v[0] = 0.3;
    v[1] = -0.1;
  };
  const std::vector<NetworkSpring> springs = {NetworkSpring{0, 1, 4.0, 0.7, 0.5, 2.0},
                                              NetworkSpring{1, 2, 2.0, 0.3, 0.5, 2.0}};
  SpringNetwork a(2, {anchor, Free(1.5, 0.4, 1.3), Free(2.0, 1.4)}, springs);
  SpringNetwork b(2, {moving, Free(1.5, 0.4, 1.3), Free(2.0, 1.4)}, springs);
  Eigen::VectorXd z(8), ra, rb;
  z << 1.5, 0.4, 0.1, -0.2, 2.0, 1.4, 0.05, 0.0;
  const Eigen::VectorXd rest = Eigen::Vector2d(1.1, 0.9);
  EvaluateDynamics(a, 1.7, z, rest, ra);
  EvaluateDynamics(b, 1.7, z, rest, rb);
  EXPECT_LT((ra - rb).norm(), 1e-14);
  EXPECT_GT(ra.norm(), 0.0);
  NetworkNode bad = Free(0, 0);
  bad.motion = moving.motion;
  ExpectInputError(
      [&] {
        SpringNetwork(2, {bad, Free(1.5, 0.4)}, {Spring(0, 1)});
      },
      {"network.nodes[0].motion"});
  ExpectInputError(
      [&] {
        SpringNetwork(2, {moving, Free(0.5, -0.2)}, {Spring(0, 1)});
      },
      {"network.springs[0].nodes", "coincide"});
}

TEST(ControlContinuation, HalvesTheStepOnFailureAndRecordsThePath) {
  // A family whose problem is broken (non-finite reference) the first time p = 1 is asked for:
  // the path stage must fail once, halve C^p and still reach p = 1.
  OscillatorExample ex;
  ex.gamma = 1e-2;
  int calls_at_one = 0;
  const ProblemFamily family = [&](double p) {
    TrackingProblem problem = MakeOscillatorProblem(ex, p);
    if (p == 1.0 && calls_at_one++ == 1) {  // call 0 is the target lookup
      ReferenceFunction bad = [](double, double* x, double* v, double* w) {
        x[0] = std::nan("");
        v[0] = 0;
        w[0] = 1;
      };
      return TrackingProblem(problem.network(), problem.horizon(), bad, problem.weights(),
                             problem.gamma());
    }
    return problem;
  };
  ContinuationOptions options;
  options.path_start = 0.5;
  options.path_increase = 1.0;  // 0.5 → 1 (fails) → 0.75 → 1
  options.gamma_start = 1e-1;
  options.gamma_decrease = 0.1;
  options.start_steps = 0;  // every stage on the requested grid (no coarse start grid)
  Eigen::VectorXd y;
  const ContinuationSummary s = SolveWithContinuation(family, 100, options, y);
  ASSERT_TRUE(s.ok()) << s.BriefReport();
  ASSERT_GE(s.path.size(), 5u);
  EXPECT_EQ(s.path[0].stage, "initial");
  EXPECT_EQ(s.path[1].stage, "path");
  EXPECT_EQ(s.path[1].path_fraction, 1.0);
  EXPECT_FALSE(s.path[1].accepted);
  EXPECT_EQ(s.path[2].path_fraction, 0.75);
  EXPECT_TRUE(s.path[2].accepted);
  EXPECT_EQ(s.path[3].path_fraction, 1.0);
  EXPECT_TRUE(s.path[3].accepted);
  EXPECT_EQ(s.path[4].stage, "gamma");
  EXPECT_DOUBLE_EQ(s.path[4].gamma, 1e-2);
  EXPECT_EQ(s.gamma, 1e-2);
}

TEST(ControlContinuation, ReportsFailureWithoutThrowing) {
  OscillatorExample ex;
  const ProblemFamily family = [&](double p) {
    TrackingProblem problem = MakeOscillatorProblem(ex, p);
    ReferenceFunction bad = [](double, double* x, double* v, double* w) {
      x[0] = std::nan("");
      v[0] = 0;
      w[0] = 1;
    };
    return TrackingProblem(problem.network(), problem.horizon(), bad, problem.weights(),
                           problem.gamma());
  };
  Eigen::VectorXd y;
  const ContinuationSummary s = SolveWithContinuation(family, 50, ContinuationOptions{}, y);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message.find("did not converge"), std::string::npos) << s.message;
  EXPECT_EQ(s.path.size(), 1u);
  EXPECT_EQ(y.size(), 2 * 2 * 50);  // the best iterate is returned
}

TEST(ControlContinuation, OptionsValidateNamingTheKey) {
  ContinuationOptions o;
  o.path_start = 0.0;
  ExpectInputError([&] { o.Validate(); }, {"path_start: must be in (0, 1] (got 0)"});
  o = ContinuationOptions{};
  o.gamma_decrease = 1.5;
  ExpectInputError([&] { o.Validate(); }, {"gamma_decrease: must be in (0, 1) (got 1.5)"});
  o = ContinuationOptions{};
  o.newton.residual_tolerance = -1;
  ExpectInputError([&] { o.Validate(); }, {"newton.residual_tolerance: must be > 0 (got -1)"});
  o = ContinuationOptions{};
  o.fixed_point.damping = 0;
  ExpectInputError([&] { o.Validate(); }, {"fixed_point.damping: must be in (0, 1] (got 0)"});
  o = ContinuationOptions{};
  o.coarse_steps = -1;
  ExpectInputError([&] { o.Validate(); }, {"coarse_steps: must be ≥ 0 (got -1)"});
  o = ContinuationOptions{};
  o.refine_factor = 1;
  ExpectInputError([&] { o.Validate(); }, {"refine_factor: must be ≥ 2 (got 1)"});
  o = ContinuationOptions{};
  o.start_steps = -3;
  ExpectInputError([&] { o.Validate(); }, {"start_steps: must be ≥ 0 (got -3)"});
  o = ContinuationOptions{};
  o.newton.threads = -2;
  ExpectInputError([&] { o.Validate(); }, {"newton.threads: must be ≥ 0 (got -2)"});
}

TEST(ControlContinuation, CoarseToFineGridsEndOnTheRequestedGrid) {
  ContinuationOptions o;
  o.coarse_steps = 512;
  o.refine_factor = 2;
  EXPECT_EQ(ContinuationGrids(4096, o, false), (std::vector<int>{512, 1024, 2048, 4096}));
  EXPECT_EQ(ContinuationGrids(1000, o, false), (std::vector<int>{500, 1000}));
  EXPECT_EQ(ContinuationGrids(512, o, false), (std::vector<int>{512}));
  EXPECT_EQ(ContinuationGrids(4096, o, true), (std::vector<int>{4096}));  // warm start: plain
  o.refine_factor = 8;
  EXPECT_EQ(ContinuationGrids(4096, o, false), (std::vector<int>{512, 4096}));
  o.coarse_steps = 100;
  EXPECT_EQ(ContinuationGrids(4096, o, false), (std::vector<int>{64, 512, 4096}));
  o.coarse_steps = 0;
  EXPECT_EQ(ContinuationGrids(4096, o, false), (std::vector<int>{4096}));
}

TEST(ControlContinuation, StartGridsLeadUpToTheCoarseGridWithDeltaContinuation) {
  ContinuationOptions o;
  o.gamma_start = 1.0;
  o.coarse_steps = 512;
  o.refine_factor = 2;
  o.start_steps = 64;
  EXPECT_EQ(StartGrids(4096, o, 1e-4, false), (std::vector<int>{64, 128, 256}));
  EXPECT_EQ(StartGrids(1000, o, 1e-4, false), (std::vector<int>{63, 125, 250}));  // N_0 = 500
  EXPECT_EQ(StartGrids(256, o, 1e-4, false), (std::vector<int>{64, 128}));        // N_0 = N = 256
  EXPECT_EQ(StartGrids(64, o, 1e-4, false), (std::vector<int>{}));
  EXPECT_EQ(StartGrids(4096, o, 1e-4, true), (std::vector<int>{}));  // warm start: plain
  EXPECT_EQ(StartGrids(4096, o, 1.0, false), (std::vector<int>{}));  // no δ continuation
  o.start_steps = 100;
  EXPECT_EQ(StartGrids(4096, o, 1e-4, false), (std::vector<int>{64, 128, 256}));
  o.start_steps = 0;
  EXPECT_EQ(StartGrids(4096, o, 1e-4, false), (std::vector<int>{}));
  o.start_steps = 64;
  o.coarse_steps = 0;
  EXPECT_EQ(StartGrids(4096, o, 1e-4, false), (std::vector<int>{}));
}

TEST(ControlStudy, MaxPositionDifferenceSamplesBothGrids) {
  std::mt19937 rng(5);
  const TrackingProblem problem = testing::RandomProblem(1, 1, 1, 0.1, rng);
  // z_a linear in time on 4 steps, z_b on 8 steps: identical functions → 0; shift → shift.
  Eigen::MatrixXd za(2, 5), zb(2, 9);
  for (int n = 0; n <= 4; ++n) za.col(n) << 0.25 * n, 1.0;
  for (int n = 0; n <= 8; ++n) zb.col(n) << 0.125 * n, 7.0;
  EXPECT_NEAR(MaxPositionDifference(problem, za, zb, 4), 0.0, 1e-15);  // velocities ignored
  zb.row(0).array() += 0.5;
  EXPECT_NEAR(MaxPositionDifference(problem, za, zb, 4), 0.5, 1e-15);
}

}  // namespace
}  // namespace moreau::control
