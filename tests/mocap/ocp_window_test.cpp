// One window of the optimal-control fill: the time step follows the network's fastest rates and
// the first Newton iterate starts from the prior with a residual of the prior's order, on a
// synthetic body and on real windows that used to start from 10¹² and 2⁶³ (an ulp of costates
// that the backward march had blown up to 2⁹³ and 2¹¹⁵); a window that fails is retried with
// fewer springs to anchors, and one at an edge of the take with its prior weighted like the
// observations.
#include "mocap/ocp_window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "mocap/io_test_util.h"
#include "mocap/ocp_test_util.h"
#include "moreau/control/pontryagin.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {
namespace {

// The fill the optimal control starts from: the candidates' weighted average, no control.
Recording PriorFill(const Recording& in) {
  GapFillOptions prior;
  prior.method = GapFillMethod::kOcp;
  prior.ocp.optimal_control = false;
  Recording base;
  FillGaps(in, FindGaps(in), prior, &base);
  return base;
}

// The index of the marker called `label` (markers() when there is none).
int MarkerIndex(const Recording& in, const std::string& label) {
  return static_cast<int>(std::find(in.labels().begin(), in.labels().end(), label) -
                          in.labels().begin());
}

// ‖F‖_∞ of the window's first iterate, on the problem it is made for (s = 1, γ = gamma_start).
double FirstResidual(const internal::OcpWindowProblem& p, Eigen::VectorXd* residual = nullptr) {
  const control::TrackingProblem start = p.target->WithGamma(p.continuation.gamma_start);
  const control::PontryaginDiscretization disc(start, p.steps);
  control::PontryaginWorkspace ws;
  Eigen::VectorXd r;
  const double norm = control::EvaluateResidual(disc, p.warm_start, ws, r);
  if (residual != nullptr) *residual = r;
  return norm;
}

TEST(MocapOcpWindow, FirstIterateOfAWellHeldMarkerIsThePriorsOrder) {
  // A marker held by five springs: damping summed over them is ~5× one spring's, which the old
  // step (ω Δt <= 0.5 for one spring) made an explicit step with |1 + Δt μ| > 1, and the costates'
  // backward march grew by that factor every step.
  const Recording truth = testing::RigidBodies(1, 6, 120, 100.0);
  Recording in = truth;
  testing::Hide(in, 2, 40, 79);
  OcpFillOptions o;
  const MarkerNetwork net = BuildMarkerNetwork(in, o.network);
  const internal::OcpWindow w{30, 89, {2}};
  internal::OcpWindowProblem p;
  internal::MakeOcpWindowProblem(in, truth, net, w, o, p);  // the prior: the truth
  ASSERT_GE(p.springs, 5);
  Eigen::VectorXd f;
  const double first = FirstResidual(p, &f);
  EXPECT_LT(first, 0.05);
  EXPECT_LT(p.warm_start.lpNorm<Eigen::Infinity>(), 10.0);
  // The invariants of the first iterate (control::FittedControlStart): per block n the position
  // rows of F^z vanish for n >= 1, the λ rows of F^ρ for every n, the ζ rows of F^ρ at n = 0.
  const int nz = 6;
  for (int n = 0; n < p.steps; ++n) {
    const auto block = f.segment(2 * nz * n, 2 * nz);
    if (n >= 1) {
      EXPECT_LT(block.segment(0, 3).lpNorm<Eigen::Infinity>(), 1e-12) << n;
    }
    EXPECT_LT(block.segment(nz, 3).lpNorm<Eigen::Infinity>(), 1e-12) << n;
    if (n == 0) {
      EXPECT_LT(block.segment(nz + 3, 3).lpNorm<Eigen::Infinity>(), 1e-12);
    }
  }
  Eigen::VectorXd y;
  int iterations = 0;
  const control::ContinuationSummary cs = internal::SolveOcpWindowProblem(p, o, y, iterations);
  ASSERT_TRUE(cs.ok()) << cs.message;
  EXPECT_EQ(cs.path.front().stiffness_scale, 1.0);  // the first attempt, no retry
  EXPECT_LE(iterations, 10);
  EXPECT_LE(cs.last_newton.final_residual, o.newton.residual_tolerance);
}

TEST(MocapOcpWindow, RealWindowsStartFromThePriorAndConverge) {
  // Eb015pr.c3d: four markers hidden together from frame 0 (the first iterate's residual was
  // 9.223e18 = 2⁶³), and one marker alone in the middle (1.1e43 before the retry).
  const Recording in = ReadRecording(testing::MocapData("Eb015pr.c3d"));
  const Recording base = PriorFill(in);
  const OcpFillOptions o;
  const MarkerNetwork net = BuildMarkerNetwork(in, o.network);
  auto marker = [&](const std::string& label) { return MarkerIndex(in, label); };
  const internal::OcpWindow windows[] = {
      {0, 51, {marker("LFT1"), marker("LTH1"), marker("PV1"), marker("PV3")}},
      {338, 359, {marker("PV2")}}};
  for (const internal::OcpWindow& w : windows) {
    internal::OcpWindowProblem p;
    internal::MakeOcpWindowProblem(in, base, net, w, o, p);
    EXPECT_LT(FirstResidual(p), 1.0) << w.first;
    Eigen::VectorXd y;
    int iterations = 0;
    const control::ContinuationSummary cs = internal::SolveOcpWindowProblem(p, o, y, iterations);
    ASSERT_TRUE(cs.ok()) << w.first << ": " << cs.message;
    EXPECT_EQ(cs.path.front().stiffness_scale, 1.0) << w.first;
    EXPECT_LE(iterations, 15) << w.first;
  }
}

// The synthetic body of FirstIterateOfAWellHeldMarkerIsThePriorsOrder: marker 2 hidden over
// frames 40..79, held by five springs to anchors, the truth as prior.
struct HeldMarkerWindow {
  Recording truth = testing::RigidBodies(1, 6, 120, 100.0);
  Recording in = truth;
  MarkerNetwork net;
  internal::OcpWindow w{30, 89, {2}};
  explicit HeldMarkerWindow(const OcpFillOptions& o) {
    testing::Hide(in, 2, 40, 79);
    net = BuildMarkerNetwork(in, o.network);
  }
  internal::OcpWindowResult Solve(const OcpFillOptions& o) const {
    return internal::SolveOcpWindow(in, truth, net, w, o);
  }
};

TEST(MocapOcpWindow, AFailedWindowIsRetriedWithFewerAnchorSprings) {
  OcpFillOptions o;
  o.newton.max_iterations = 1;  // no attempt converges
  const HeldMarkerWindow body(o);
  const internal::OcpWindowResult retried = body.Solve(o);
  EXPECT_FALSE(IsSuccess(retried.termination));
  EXPECT_NE(retried.message.find("; with 4 anchor springs per marker: "), std::string::npos)
      << retried.message;
  EXPECT_LE(retried.springs, 4);  // one free marker, only springs to anchors
  EXPECT_LE(retried.anchors, 4);
  // The iterations of both attempts: the first one alone (retry off), the retry alone (the
  // options' anchor_springs already 4: no retry).
  OcpFillOptions first = o;
  first.retry_anchor_springs = 0;
  const internal::OcpWindowResult alone = body.Solve(first);
  EXPECT_FALSE(IsSuccess(alone.termination));
  EXPECT_EQ(alone.message.find("anchor springs"), std::string::npos) << alone.message;
  EXPECT_GE(alone.springs, 5);
  OcpFillOptions four = o;
  four.anchor_springs = 4;
  const internal::OcpWindowResult last = body.Solve(four);
  EXPECT_EQ(last.springs, retried.springs);
  EXPECT_EQ(last.message.find("anchor springs"), std::string::npos) << last.message;
  EXPECT_GT(alone.newton_iterations, 0);
  EXPECT_GT(last.newton_iterations, 0);
  EXPECT_EQ(retried.newton_iterations, alone.newton_iterations + last.newton_iterations);
}

TEST(MocapOcpWindow, AWindowThatConvergesIsNotRetried) {
  const OcpFillOptions o;
  const HeldMarkerWindow body(o);
  const internal::OcpWindowResult solved = body.Solve(o);
  ASSERT_TRUE(IsSuccess(solved.termination)) << solved.message;
  EXPECT_GE(solved.springs, 5);  // every spring to anchors: the first attempt's network
  EXPECT_EQ(solved.message.find("anchor springs"), std::string::npos);
  EXPECT_LE(solved.newton_iterations, 10);
}

TEST(MocapOcpWindow, AFailedWindowAtTheTakesEndIsSolvedAgainWithItsPriorWeightedLikeObservations) {
  OcpFillOptions o;
  o.newton.max_iterations = 1;  // no attempt converges
  HeldMarkerWindow body(o);
  const internal::OcpWindowResult inside = body.Solve(o);  // frames 40..79 inside the window
  EXPECT_EQ(inside.message.find("weighted like the observations"), std::string::npos)
      << inside.message;
  body.in = body.truth;
  testing::Hide(body.in, 2, 80, 119);  // to the take's end
  body.w = internal::OcpWindow{70, 119, {2}};
  const internal::OcpWindowResult edge = body.Solve(o);
  EXPECT_FALSE(IsSuccess(edge.termination));
  EXPECT_NE(edge.message.find("; with 4 anchor springs per marker: "), std::string::npos);
  EXPECT_NE(edge.message.find("; the edge's prior weighted like the observations: "),
            std::string::npos)
      << edge.message;
  // Not when the prior weighs no more than the observations: the same problem.
  OcpFillOptions light = o;
  light.prior_weight = light.observed_weight;
  const internal::OcpWindowResult same = body.Solve(light);
  EXPECT_EQ(same.message.find("weighted like the observations"), std::string::npos);
}

TEST(MocapOcpWindow, TheHandHiddenAtTheTakesEndConvergesWithItsPriorWeightedLikeObservations) {
  // upper_body_25hz.c3d: the left hand's three markers hidden over the last 0.5 s (frames
  // 657..669). With the prior weighted 10× the observations Newton stalls in every attempt (line
  // search without decrease); weighted like them, the window converges from the prior.
  const Recording truth = ReadRecording(testing::MocapData("upper_body_25hz.c3d"));
  Recording in = truth;
  std::vector<int> hand;
  for (const char* label : {"LWRA", "LWRB", "LPALA1"}) {
    hand.push_back(MarkerIndex(in, label));
    ASSERT_LT(hand.back(), in.markers());
    testing::Hide(in, hand.back(), 657, 669);
  }
  std::sort(hand.begin(), hand.end());
  const Recording base = PriorFill(in);
  const OcpFillOptions o;
  const MarkerNetwork net = BuildMarkerNetwork(in, o.network);
  const internal::OcpWindow w{654, 669, hand};
  internal::OcpWindowProblem p;
  internal::MakeOcpWindowProblem(in, base, net, w, o, p, true);
  Eigen::VectorXd y;
  int iterations = 0;
  const control::ContinuationSummary cs = internal::SolveOcpWindowProblem(p, o, y, iterations);
  ASSERT_TRUE(cs.ok()) << cs.message;
  EXPECT_EQ(cs.path.front().stiffness_scale, 1.0);  // the first attempt
  EXPECT_LE(cs.last_newton.final_residual, o.newton.residual_tolerance);
}

}  // namespace
}  // namespace moreau::mocap
