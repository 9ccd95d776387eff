#include "moreau/mocap/fill.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mocap/synthetic.h"
#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

using testing::GapMaxError;
using testing::Hide;
using testing::MakeCubicRecording;
using testing::MakeLineRecording;
using testing::MakeLowRankRecording;
using testing::MakeRigidBodyRecording;

FillOptions With(FillMethod method) {
  FillOptions options;
  options.method = method;
  return options;
}

TEST(FillGaps, StraightLineAtConstantSpeedIsFilledExactlyByTheInterpolants) {
  const Recording truth = MakeLineRecording(4, 120, 100.0);
  Recording gapped = truth;
  const Gap gap = Hide(gapped, 2, 30, 64);
  for (FillMethod method : {FillMethod::kLinear, FillMethod::kSpline, FillMethod::kPchip}) {
    Recording out;
    const FillSummary summary = FillGaps(gapped, {gap}, With(method), &out);
    ASSERT_EQ(summary.gaps.size(), 1u);
    EXPECT_EQ(summary.gaps[0].status, GapStatus::kFilled) << summary.gaps[0].message;
    EXPECT_EQ(summary.samples_filled, gap.length());
    EXPECT_LT(GapMaxError(out, truth, gap), 1e-9) << ToString(method);
  }
}

TEST(FillGaps, CubicInTimeIsFilledExactlyBySplineButNotByLinear) {
  const Recording truth = MakeCubicRecording(3, 160, 100.0);
  Recording gapped = truth;
  const Gap gap = Hide(gapped, 1, 50, 89);
  Recording spline, linear;
  FillGaps(gapped, {gap}, With(FillMethod::kSpline), &spline);
  FillGaps(gapped, {gap}, With(FillMethod::kLinear), &linear);
  EXPECT_LT(GapMaxError(spline, truth, gap), 1e-8);
  EXPECT_GT(GapMaxError(linear, truth, gap), 1.0);
}

TEST(FillGaps, TurningRigidBodyIsFilledExactlyByRigidEvenWithTwoMarkersMissing) {
  const Recording truth = MakeRigidBodyRecording(6, 200, 100.0, 7);
  Recording gapped = truth;
  const Gap a = Hide(gapped, 0, 40, 130);
  const Gap b = Hide(gapped, 3, 60, 100);  // missing at the same time as marker 0
  Recording out;
  const FillSummary summary = FillGaps(gapped, {a, b}, With(FillMethod::kRigid), &out);
  EXPECT_EQ(summary.gaps_filled, 2) << summary.message;
  EXPECT_LT(GapMaxError(out, truth, a), 1e-8);
  EXPECT_LT(GapMaxError(out, truth, b), 1e-8);
  // Linear interpolation cannot follow the rotation.
  FillGaps(gapped, {a, b}, With(FillMethod::kLinear), &out);
  EXPECT_GT(GapMaxError(out, truth, a), 1.0);
}

TEST(FillGaps, LowRankMotionIsFilledByPcaIncludingOverlappingAndEdgeGaps) {
  const Recording truth = MakeLowRankRecording(12, 300, 100.0, 3, 11);
  Recording gapped = truth;
  const Gap a = Hide(gapped, 5, 100, 180);
  const Gap b = Hide(gapped, 8, 150, 220);
  const Gap edge = Hide(gapped, 2, 0, 20);
  Recording out;
  const FillSummary summary = FillGaps(gapped, {a, b, edge}, With(FillMethod::kPca), &out);
  EXPECT_EQ(summary.gaps_filled, 3) << summary.message;
  for (const Gap& gap : {a, b, edge}) EXPECT_LT(GapMaxError(out, truth, gap), 1e-6);
}

TEST(FillGaps, GapsAtTheEdgesAreSkippedAndStayMissing) {
  const Recording truth = MakeRigidBodyRecording(5, 80, 100.0, 3);
  Recording gapped = truth;
  const Gap start = Hide(gapped, 1, 0, 9);
  const Gap end = Hide(gapped, 2, 70, 79);
  for (FillMethod method :
       {FillMethod::kLinear, FillMethod::kSpline, FillMethod::kPchip, FillMethod::kRigid}) {
    Recording out;
    const FillSummary summary = FillGaps(gapped, {start, end}, With(method), &out);
    EXPECT_EQ(summary.gaps_filled, 0);
    for (const GapReport& report : summary.gaps) {
      EXPECT_EQ(report.status, GapStatus::kSkippedEdge) << ToString(method);
      EXPECT_FALSE(report.message.empty());
    }
    EXPECT_FALSE(out.observed(0, 1));
    EXPECT_TRUE(std::isnan(out.point(79, 2)[0]));
  }
}

TEST(FillGaps, TooFewSamplesTooLongAndNoDonorsAreReported) {
  const Recording truth = MakeLineRecording(3, 100, 200.0);
  Recording gapped = truth;
  Hide(gapped, 0, 0, 9);
  const Gap after_single = Hide(gapped, 0, 11, 20);  // only frame 10 observed before it
  Recording out;
  EXPECT_EQ(FillGaps(gapped, {after_single}, With(FillMethod::kSpline), &out).gaps[0].status,
            GapStatus::kTooFewSamples);
  EXPECT_EQ(FillGaps(gapped, {after_single}, With(FillMethod::kPchip), &out).gaps[0].status,
            GapStatus::kTooFewSamples);
  EXPECT_EQ(FillGaps(gapped, {after_single}, With(FillMethod::kLinear), &out).gaps[0].status,
            GapStatus::kFilled);
  // Three markers: two candidates, fewer than the three donors rigid needs.
  EXPECT_EQ(FillGaps(gapped, {after_single}, With(FillMethod::kRigid), &out).gaps[0].status,
            GapStatus::kNoDonors);

  const Gap long_gap = Hide(gapped, 1, 30, 59);  // 30 frames = 0.15 s
  FillOptions options = With(FillMethod::kLinear);
  options.max_gap_seconds = 0.1;
  const FillSummary summary = FillGaps(gapped, {long_gap}, options, &out);
  EXPECT_EQ(summary.gaps[0].status, GapStatus::kTooLong);
  EXPECT_FALSE(out.observed(45, 1));
  options.max_gap_seconds = 0.15;
  EXPECT_EQ(FillGaps(gapped, {long_gap}, options, &out).gaps[0].status, GapStatus::kFilled);
}

TEST(FillGaps, PcaWithoutOtherMarkersOrCompleteFramesIsReported) {
  const Recording truth = MakeLowRankRecording(4, 60, 100.0, 2, 5);
  Recording gapped = truth;
  const Gap gap = Hide(gapped, 0, 20, 30);
  for (int m = 1; m < 4; ++m) Hide(gapped, m, 25, 25);
  Recording out;
  EXPECT_EQ(FillGaps(gapped, {gap}, With(FillMethod::kPca), &out).gaps[0].status,
            GapStatus::kNoDonors);
  Recording sparse = truth;
  const Gap gap2 = Hide(sparse, 0, 20, 30);
  for (std::int64_t f = 0; f < 60; f += 2) {
    if (f < 20 || f > 30) sparse.ClearPoint(f, 1);
  }
  FillOptions options = With(FillMethod::kPca);
  options.pca.min_complete_frames = 40;
  options.pca.distal_threshold = 1e6;  // keep marker 1 although it has gaps
  EXPECT_EQ(FillGaps(sparse, {gap2}, options, &out).gaps[0].status, GapStatus::kTooFewSamples);
}

TEST(FillGaps, PchipDoesNotOvershootMonotoneDataWhereTheSplineDoes) {
  // x rises steeply (30 per frame) up to frame 15, then reaches a plateau of 100 after the gap.
  Recording r({"A"}, 40, 100.0);
  for (std::int64_t f = 0; f < 40; ++f) {
    const double x = f > 25 ? 100.0 : std::max(0.0, 30.0 * static_cast<double>(f - 12));
    r.SetPoint(f, 0, Eigen::Vector3d(x, 0.0, 0.0));
  }
  const Gap gap = Hide(r, 0, 16, 25);
  Recording pchip, spline;
  FillGaps(r, {gap}, With(FillMethod::kPchip), &pchip);
  FillGaps(r, {gap}, With(FillMethod::kSpline), &spline);
  double previous = 90.0, spline_high = 0.0;
  for (std::int64_t f = gap.first; f <= gap.last + 1; ++f) {
    const double x = pchip.point(f, 0)[0];
    EXPECT_GE(x, previous);
    EXPECT_LE(x, 100.0);
    previous = x;
    spline_high = std::max(spline_high, spline.point(f, 0)[0]);
  }
  EXPECT_GT(spline_high, 100.0);  // the spline overshoots the plateau; pchip does not
}

TEST(FillGaps, FillingInPlaceEqualsFillingIntoACopy) {
  const Recording truth = MakeRigidBodyRecording(5, 80, 100.0, 9);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 0, 10, 30), Hide(gapped, 4, 20, 50)};
  ASSERT_EQ(FindGaps(gapped).size(), 2u);
  Recording copy;
  FillGaps(gapped, gaps, With(FillMethod::kRigid), &copy);
  FillGaps(gapped, gaps, With(FillMethod::kRigid), &gapped);
  for (std::int64_t f = 0; f < 80; ++f) {
    for (int m = 0; m < 5; ++m) EXPECT_EQ(copy.point(f, m), gapped.point(f, m));
  }
  EXPECT_TRUE(FindGaps(gapped).empty());
}

TEST(FillGaps, SummaryJsonNamesStatusesAndSettings) {
  const Recording truth = MakeLineRecording(3, 50, 100.0);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 0, 0, 4), Hide(gapped, 1, 10, 19)};
  Recording out;
  const FillSummary summary = FillGaps(gapped, gaps, With(FillMethod::kPchip), &out);
  const nlohmann::json j = summary.ToJson();
  EXPECT_EQ(j["gaps_filled"], 1);
  EXPECT_EQ(j["gaps_unfilled"], 1);
  EXPECT_EQ(j["samples_filled"], 10);
  EXPECT_EQ(j["gaps"][0]["status"], "skipped_edge");
  EXPECT_EQ(j["gaps"][1]["status"], "filled");
  EXPECT_EQ(j["gaps"][1]["label"], "M1");
  EXPECT_EQ(j["settings"]["method"], "pchip");
  EXPECT_EQ(j["termination"], "completed");
  EXPECT_TRUE(summary.ok());
}

TEST(FillGaps, AMarkerMissingInEveryFrameIsNeverObservedForEveryMethod) {
  const Recording truth = MakeLineRecording(4, 50, 100.0);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 2, 0, 49), Hide(gapped, 1, 10, 19)};
  for (FillMethod method : AllFillMethods()) {
    Recording out;
    const FillSummary summary = FillGaps(gapped, gaps, With(method), &out);
    EXPECT_EQ(summary.gaps[0].status, GapStatus::kNeverObserved) << ToString(method);
    EXPECT_EQ(summary.gaps[0].outcome, GapOutcome::kUnfillable) << ToString(method);
    for (std::int64_t f = 0; f < 50; ++f) EXPECT_FALSE(out.observed(f, 2));
    const GapOutcomeCounts counts = GapOutcomeCounts::Of(summary.gaps);
    EXPECT_EQ(counts.unfillable_by_status.at("never_observed"), 1) << ToString(method);
  }
}

TEST(FillGaps, OutcomeCountsAndMessageAgreeWithTheGaps) {
  // linear: one gap filled, one at the start (skipped_edge), one longer than 0.05 s (too_long).
  const Recording truth = MakeLineRecording(3, 60, 100.0);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 0, 10, 12), Hide(gapped, 1, 0, 3),
                                 Hide(gapped, 2, 20, 29)};
  FillOptions options = With(FillMethod::kLinear);
  options.max_gap_seconds = 0.05;
  Recording out;
  const FillSummary summary = FillGaps(gapped, gaps, options, &out);
  EXPECT_EQ(summary.message,
            "3 gaps: 1 filled by linear, 2 unfillable (skipped_edge 1, too_long 1)");
  const nlohmann::json j = summary.ToJson();
  EXPECT_EQ(j["outcomes"]["gaps"], 3);
  EXPECT_EQ(j["outcomes"]["baseline"], 1);
  EXPECT_EQ(j["outcomes"]["unfillable"], 2);
  EXPECT_EQ(j["outcomes"]["optimal_control"], 0);
  EXPECT_EQ(j["outcomes"]["prior"], 0);
  EXPECT_EQ(j["outcomes"]["unfillable_by_status"]["too_long"], 1);
  EXPECT_EQ(j["gaps"][0]["outcome"], "baseline");
  EXPECT_EQ(j["gaps"][1]["outcome"], "unfillable");
  EXPECT_TRUE(j["gaps"][0]["prior_reason"].is_null());
  EXPECT_EQ(GapOutcomeCounts{}.Describe("linear"), "0 gaps");
}

TEST(FillGaps, MethodAndStatusNamesRoundTrip) {
  for (FillMethod method : AllFillMethods()) {
    EXPECT_EQ(ParseFillMethod(ToString(method)), method);
  }
  for (auto status :
       {GapStatus::kFilled, GapStatus::kSkippedEdge, GapStatus::kTooLong, GapStatus::kTooFewSamples,
        GapStatus::kNoDonors, GapStatus::kFailed, GapStatus::kNeverObserved}) {
    EXPECT_EQ(ParseGapStatus(ToString(status)), status);
  }
  try {
    ParseFillMethod("cubic");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'cubic'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("pchip"), std::string::npos);
  }
}

// The message of the InputError that options.Validate() throws.
std::string ValidationMessage(const FillOptions& options) {
  try {
    options.Validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FillGaps, OptionValidationNamesTheField) {
  EXPECT_EQ(ValidationMessage(FillOptions{}), "");
  FillOptions o;
  o.interpolation.samples_per_side = 1;
  EXPECT_NE(ValidationMessage(o).find("interpolation.samples_per_side: must be ≥ 2 (got 1)"),
            std::string::npos);
  o = {};
  o.rigid.donors = 2;
  EXPECT_NE(ValidationMessage(o).find("rigid.donors: must be ≥ 3 (got 2)"), std::string::npos);
  o = {};
  o.max_gap_seconds = -1.0;
  EXPECT_NE(ValidationMessage(o).find("max_gap_seconds: must be ≥ 0 (got -1)"), std::string::npos);
  o = {};
  o.pca.explained_fraction = 1.5;
  EXPECT_NE(ValidationMessage(o).find("pca.explained_fraction: must be in (0, 1] (got 1.5)"),
            std::string::npos);
  o = {};
  o.pca.missing_marker_weight = 0.0;
  EXPECT_NE(ValidationMessage(o).find("pca.missing_marker_weight: must be in (0, 1] (got 0)"),
            std::string::npos);
  o = {};
  o.pca.tolerance = 0.0;
  EXPECT_NE(ValidationMessage(o).find("pca.tolerance: must be > 0 (got 0)"), std::string::npos);
}

TEST(FillGaps, MeetingEndsRemovesTheErrorsAtTheBoundingSamples) {
  // linear through the gap widened by one frame, corrected to meet the two bounding samples, is
  // the straight line between them again: FillGaps' own linear fill. A gap at the start of the
  // recording (pca can fill it) is widened by its one observed side and shifted by the widened
  // fill's error there.
  const Recording truth = MakeRigidBodyRecording(5, 60, 100.0, 3);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 1, 20, 34), Hide(gapped, 2, 0, 9)};
  for (FillMethod method : {FillMethod::kLinear, FillMethod::kPca}) {
    Recording plain, meeting;
    const FillSummary a = FillGaps(gapped, gaps, With(method), &plain);
    const FillSummary b = FillGapsMeetingEnds(gapped, gaps, With(method), &meeting);
    ASSERT_EQ(a.gaps.size(), b.gaps.size());
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      EXPECT_EQ(a.gaps[i].status, b.gaps[i].status) << ToString(method) << " gap " << i;
    }
    EXPECT_EQ(b.method, ToString(method));
    const Gap& edge = gaps[1];
    if (!b.gaps[1].filled()) continue;
    Recording wider = gapped;
    wider.ClearPoint(edge.last + 1, edge.marker);
    const GapFill wide = FillGap(wider, Gap{edge.marker, edge.first, edge.last + 1}, With(method));
    ASSERT_EQ(wide.status, GapStatus::kFilled);
    const Eigen::Vector3d error =
        gapped.point(edge.last + 1, edge.marker) - wide.points.col(edge.length());
    for (std::int64_t f = edge.first; f <= edge.last; ++f) {
      const Eigen::Vector3d shifted = wide.points.col(f - edge.first) + error;
      EXPECT_EQ(shifted, meeting.point(f, edge.marker)) << "frame " << f;
    }
  }
  Recording plain, meeting;
  FillGaps(gapped, gaps, With(FillMethod::kLinear), &plain);
  FillGapsMeetingEnds(gapped, gaps, With(FillMethod::kLinear), &meeting);
  for (std::int64_t f = gaps[0].first; f <= gaps[0].last; ++f) {
    EXPECT_LT((plain.point(f, 1) - meeting.point(f, 1)).norm(), 1e-9) << "frame " << f;
  }
}

TEST(FillGaps, AGapThatDoesNotMatchTheRecordingIsAnInputError) {
  const Recording truth = MakeLineRecording(2, 20, 100.0);
  Recording out;
  EXPECT_THROW(FillGaps(truth, {Gap{0, 5, 6}}, FillOptions{}, &out), InputError);  // observed
  EXPECT_THROW(FillGaps(truth, {Gap{2, 5, 6}}, FillOptions{}, &out), InputError);  // marker
  EXPECT_THROW(FillGaps(truth, {Gap{0, 6, 5}}, FillOptions{}, &out), InputError);  // order
}

}  // namespace
}  // namespace moreau::mocap
