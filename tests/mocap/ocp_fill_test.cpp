// Gap filling by optimal control of the spring network: rigid-body truth, a reachable reference,
// whole segments hidden, windows around gaps, fallback, bad settings.
#include "moreau/mocap/ocp_fill.h"

#include <gtest/gtest.h>

#include <cstring>

#include "mocap/ocp_test_util.h"
#include "moreau/common/error.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/gap_fill.h"

namespace moreau::mocap {
namespace {

TEST(MocapOcpFill, RigidBodyHiddenMarkerIsRecovered) {
  // By the optimal control, and by the prior alone with the optimal control off.
  const Recording truth = testing::RigidBodies(1, 6, 160, 100.0);
  Recording in = truth;
  const Gap gap = testing::Hide(in, 2, 50, 99);  // 0.5 s
  for (const bool optimal_control : {true, false}) {
    Recording out;
    OcpFillOptions o;
    o.optimal_control = optimal_control;
    const testing::Baselines baselines(in, {gap}, o.candidates);
    const OcpFillSummary s = FillGapsOcp(in, {gap}, baselines.candidates, o, &out);
    ASSERT_TRUE(s.ok()) << s.message << " " << s.gaps[0].message;
    ASSERT_EQ(s.gaps.size(), 1u);
    const OcpGapReport& r = s.gaps[0];
    EXPECT_EQ(r.outcome, optimal_control ? OcpOutcome::kSolved : OcpOutcome::kPrior);
    EXPECT_EQ(r.label, "B0M2");
    EXPECT_EQ(r.free_nodes, 1);
    EXPECT_EQ(r.newton_iterations > 0, optimal_control);
    EXPECT_LE(r.residual, OcpFillOptions{}.newton.residual_tolerance);
    EXPECT_LT(testing::GapMaxError(out, truth, gap), 1e-3);  // metres
    // Only the gap was written.
    for (std::int64_t f = 0; f < in.frames(); ++f) {
      for (int m = 0; m < in.markers(); ++m) {
        if (in.observed(f, m)) {
          EXPECT_EQ(out.point(f, m), in.point(f, m));
        }
      }
    }
    const nlohmann::json j = s.ToJson(in);
    EXPECT_EQ(j["gaps"][0]["status"], optimal_control ? "ocp" : "prior");
    EXPECT_EQ(j["gaps"][0]["fallback_method"], "");
    EXPECT_TRUE(j.contains("settings"));
    EXPECT_EQ(j["network"]["springs"].size(), s.network.springs.size());
    EXPECT_EQ(r.anchors >= 3, optimal_control);  // a window was built only for the solve
  }
}

TEST(MocapOcpFill, ThroughFillGapsARigidBodyHiddenMarkerIsRecovered) {
  // Method ocp through gap_fill.h with its baseline candidates, the prior alone and with the
  // optimal control; FillGap (one gap, as the evaluation calls it) gives the same fill.
  const Recording truth = testing::RigidBodies(1, 6, 160, 100.0);
  Recording in = truth;
  const Gap gap = testing::Hide(in, 2, 50, 99);
  for (const bool optimal_control : {false, true}) {
    GapFillOptions o;
    o.method = GapFillMethod::kOcp;
    o.ocp.optimal_control = optimal_control;
    Recording out;
    const FillSummary summary = FillGaps(in, {gap}, o, &out);
    ASSERT_EQ(summary.gaps_filled, 1) << summary.message;
    EXPECT_EQ(summary.method, "ocp");
    EXPECT_EQ(summary.ToJson()["gaps"][0]["method"], "ocp");
    const std::string said = optimal_control ? "optimal control" : "prior: rigid";
    EXPECT_EQ(summary.gaps[0].message.find(said), 0u) << summary.gaps[0].message;
    EXPECT_LT(testing::GapMaxError(out, truth, gap), 1e-3);  // metres
    const GapFill one = FillGap(in, gap, o);
    ASSERT_EQ(one.status, GapStatus::kFilled);
    for (std::int64_t f = gap.first; f <= gap.last; ++f) {
      EXPECT_EQ(one.points.col(f - gap.first), out.point(f, gap.marker));
    }
  }
}

TEST(MocapOcpFill, OutcomeNamesRoundTrip) {
  // The names reports and summary.json use.
  for (OcpOutcome outcome : {OcpOutcome::kSolved, OcpOutcome::kPrior, OcpOutcome::kFallback}) {
    EXPECT_EQ(ParseOcpOutcome(ToString(outcome)), outcome);
  }
  EXPECT_EQ(ToString(OcpOutcome::kSolved), "ocp");
  EXPECT_EQ(ToString(OcpOutcome::kFallback), "fallback");
  EXPECT_THROW(ParseOcpOutcome("solved"), InputError);
}

TEST(MocapOcpFill, ReachableReferenceIsReproduced) {
  // The candidate is the truth itself: the reference is reachable by the network (distances at
  // the middle of their bounds), tracked with full weight; with a small γ (continuation from
  // the default) the optimal trajectory reproduces it.
  const Recording truth = testing::RigidBodies(1, 5, 120, 100.0);
  Recording in = truth;
  const Gap gap = testing::Hide(in, 0, 40, 79);
  OcpFillOptions o;
  o.optimal_control = true;
  o.prior_weight = 1.0;
  o.gamma = 1e-4;
  Recording out;
  const OcpFillSummary s = FillGapsOcp(in, {gap}, {CandidateFill{"truth", &truth}}, o, &out);
  ASSERT_TRUE(s.ok()) << s.gaps[0].message;
  EXPECT_EQ(s.methods, std::vector<std::string>{"truth"});
  EXPECT_DOUBLE_EQ(s.gaps[0].candidate_weights[0], 1.0);
  EXPECT_LT(testing::GapMaxError(out, truth, gap), 1e-4);
}

TEST(MocapOcpFill, MarkersHiddenTogetherAreSolvedInOneWindow) {
  const Recording truth = testing::RigidBodies(2, 6, 160, 100.0);
  Recording in = truth;
  // Two markers of body 0 hidden together, overlapping in time; a gap far away in body 1.
  const std::vector<Gap> gaps = {testing::Hide(in, 0, 60, 99), testing::Hide(in, 1, 55, 95),
                                 testing::Hide(in, 8, 20, 30)};
  Recording out;
  OcpFillOptions o;
  o.optimal_control = true;
  // Springs within each 6-marker body only (with more partners, loose springs across the bodies
  // pull the solved markers off the body by ~1 mm; docs/mocap.md, limits).
  o.network.partners = 4;
  const testing::Baselines baselines(in, gaps, o.candidates);
  const OcpFillSummary s = FillGapsOcp(in, gaps, baselines.candidates, o, &out);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(s.windows, 2);
  EXPECT_EQ(s.gaps[0].window, s.gaps[1].window);
  EXPECT_NE(s.gaps[0].window, s.gaps[2].window);
  EXPECT_EQ(s.gaps[0].free_nodes, 2);
  EXPECT_EQ(s.gaps[2].free_nodes, 1);
  // The window spans the gaps and the padding only (10 frames at 100 Hz, 0.1 s).
  EXPECT_EQ(s.gaps[2].window_first, 10);
  EXPECT_EQ(s.gaps[2].window_last, 40);
  EXPECT_EQ(s.gaps[0].window_first, 45);
  EXPECT_EQ(s.gaps[0].window_last, 109);
  for (const Gap& g : gaps)
    EXPECT_LT(testing::GapMaxError(out, truth, g), 1e-3) << "marker " << g.marker;
}

TEST(MocapOcpFillSlow, WholeSegmentHiddenIsFilled) {
  // Every marker of body 0 hidden at once: no anchor is left, the network carries the segment
  // from its padding; the fill is complete and keeps the body's distances.
  const Recording truth = testing::RigidBodies(1, 4, 80, 100.0);
  Recording in = truth;
  std::vector<Gap> gaps;
  for (int m = 0; m < 4; ++m) gaps.push_back(testing::Hide(in, m, 30, 45));
  Recording out;
  const testing::Baselines baselines(in, gaps, {FillMethod::kSpline});
  OcpFillOptions o;
  o.optimal_control = true;
  const OcpFillSummary s = FillGapsOcp(in, gaps, baselines.candidates, o, &out);
  EXPECT_EQ(s.windows, 1);
  EXPECT_EQ(s.gaps[0].free_nodes, 4);
  EXPECT_EQ(s.gaps[0].anchors, 0);
  for (const Gap& g : gaps) {
    for (std::int64_t f = g.first; f <= g.last; ++f) {
      ASSERT_TRUE(out.point(f, g.marker).allFinite());
    }
  }
  for (const MarkerSpring& sp : s.network.springs) {
    for (std::int64_t f = 30; f <= 45; ++f) {
      const double d = (out.point(f, sp.a) - out.point(f, sp.b)).norm();
      EXPECT_NEAR(d, sp.mean, 0.05 * sp.mean) << "frame " << f;
    }
  }
}

TEST(MocapOcpFill, FailedWindowFallsBackToThePrior) {
  const Recording truth = testing::RigidBodies(1, 6, 100, 100.0);
  Recording in = truth;
  const Gap gap = testing::Hide(in, 4, 30, 60);
  OcpFillOptions o;
  o.optimal_control = true;
  o.newton.max_iterations = 1;
  o.newton.residual_tolerance = 1e-300;  // cannot be met: every solve fails
  Recording out;
  const testing::Baselines baselines(in, {gap}, {FillMethod::kRigid});
  const OcpFillSummary s = FillGapsOcp(in, {gap}, baselines.candidates, o, &out);
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.fallbacks, 1);
  EXPECT_EQ(s.gaps[0].outcome, OcpOutcome::kFallback);
  EXPECT_EQ(s.ToJson(in)["gaps"][0]["status"], "fallback");
  EXPECT_EQ(s.ToJson(in)["gaps"][0]["fallback_method"], "prior");
  EXPECT_FALSE(s.gaps[0].message.empty());
  EXPECT_LT(testing::GapMaxError(out, truth, gap),
            1e-9);  // the prior (rigid) is exact on a rigid body
}

std::string FillError(const Recording& in, const std::vector<Gap>& gaps, const OcpFillOptions& o) {
  Recording out;
  return testing::InputErrorOf([&] {
    FillGapsOcp(in, gaps, {CandidateFill{"self", &in}}, o, &out);
  });
}

TEST(MocapOcpFill, BadSettingsAreOneInputError) {
  const Recording truth = testing::RigidBodies(1, 5, 40, 100.0);
  Recording in = truth;
  const Gap gap = testing::Hide(in, 1, 10, 20);
  OcpFillOptions o;
  o.prior_weight = -1.0;
  EXPECT_NE(FillError(in, {gap}, o).find("prior_weight: must be ≥ 0 (got -1)"), std::string::npos);
  o = {};
  o.padding_seconds = 1.0;  // 100 frames of padding, 40 frames of recording
  EXPECT_NE(FillError(in, {gap}, o).find("padding_seconds: the window padding"), std::string::npos);
  o = {};
  o.gamma = 0.0;
  EXPECT_NE(FillError(in, {gap}, o).find("gamma: must be > 0 (got 0)"), std::string::npos);
  // A marker never seen has no partners.
  Recording lonely = truth;
  const Gap all = testing::Hide(lonely, 3, 0, 39);
  EXPECT_NE(FillError(lonely, {all}, {}).find("no partners"), std::string::npos);
}

TEST(MocapOcpFill, ABadGapGetsTheBaselineFillsMessage) {
  // Over observed samples, past the recording's end, of no marker: one check, one wording, from
  // the ocp layer, the baseline fills and method ocp through gap_fill.h alike.
  const Recording truth = testing::RigidBodies(1, 5, 40, 100.0);
  Recording in = truth;
  testing::Hide(in, 1, 10, 20);
  GapFillOptions ocp;
  ocp.method = GapFillMethod::kOcp;
  for (const Gap& bad : {Gap{2, 5, 8}, Gap{1, 10, 60}, Gap{9, 10, 20}}) {
    const std::string expected = testing::InputErrorOf([&] { CheckGaps(in, {bad}); });
    EXPECT_EQ(expected.find("gaps[0] (marker "), 0u) << expected;
    EXPECT_EQ(FillError(in, {bad}, {}), expected);
    Recording out;
    EXPECT_EQ(testing::InputErrorOf([&] { FillGaps(in, {bad}, FillOptions{}, &out); }), expected);
    EXPECT_EQ(testing::InputErrorOf([&] { FillGaps(in, {bad}, ocp, &out); }), expected);
  }
}

TEST(MocapOcpFill, EvaluationWithOcpIsIndependentOfTheThreadCount) {
  const Recording truth = testing::RigidBodies(2, 5, 120, 100.0);
  EvaluationOptions o;
  o.methods = {GapFillMethod::kRigid, GapFillMethod::kOcp};
  o.gap_seconds = {0.1, 0.2};
  o.trials = 2;
  o.seed = 5;
  o.fill.ocp.optimal_control = true;
  o.fill.ocp.network.partners = 4;  // springs within each 5-marker body: quick solves
  o.threads = 1;
  const EvaluationSummary one = EvaluateFillMethods(truth, o);
  o.threads = 2;
  const EvaluationSummary two = EvaluateFillMethods(truth, o);
  ASSERT_EQ(one.rows.size(), two.rows.size());
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    EXPECT_EQ(one.rows[i].status, GapStatus::kFilled);
    EXPECT_EQ(std::memcmp(&one.rows[i].mean_error, &two.rows[i].mean_error, sizeof(double)), 0)
        << i;
    EXPECT_EQ(std::memcmp(&one.rows[i].max_error, &two.rows[i].max_error, sizeof(double)), 0);
    EXPECT_EQ(one.rows[i].outcome, two.rows[i].outcome);
    // Each row says what filled it; the ocp statistics count the rows by it.
    EXPECT_EQ(one.rows[i].outcome, one.rows[i].method == GapFillMethod::kRigid
                                       ? GapOutcome::kBaseline
                                       : one.rows[i].outcome);
    if (one.rows[i].method == GapFillMethod::kOcp) {
      EXPECT_TRUE(one.rows[i].outcome == GapOutcome::kOptimalControl ||
                  one.rows[i].outcome == GapOutcome::kPrior);
    }
  }
  for (const EvaluationStatistics& s : one.statistics) {
    int solved = 0, prior = 0;
    for (const EvaluationRow& r : one.rows) {
      if (r.method != s.method || r.gap_seconds != s.gap_seconds) continue;
      solved += r.outcome == GapOutcome::kOptimalControl ? 1 : 0;
      prior += r.outcome == GapOutcome::kPrior ? 1 : 0;
    }
    EXPECT_EQ(s.optimal_control, solved);
    EXPECT_EQ(s.prior, prior);
    EXPECT_EQ(s.optimal_control + s.prior, s.method == GapFillMethod::kOcp ? s.gaps : 0);
  }
}

}  // namespace
}  // namespace moreau::mocap
