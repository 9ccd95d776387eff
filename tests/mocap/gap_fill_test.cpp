// Gap filling by a method named by the user (gap_fill.h): the baseline methods as fill.h fills
// them, ocp over the baseline candidates, the names, the settings.
#include "moreau/mocap/gap_fill.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "mocap/ocp_test_util.h"
#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

using testing::Hide;
using testing::MakeRigidBodyRecording;

TEST(GapFill, MethodNamesAreTheBaselineNamesThenAverageThenOcp) {
  const std::vector<GapFillMethod> methods = AllGapFillMethods();
  ASSERT_EQ(methods.size(), AllFillMethods().size() + 2);
  EXPECT_EQ(ToString(methods[methods.size() - 2]), "average");
  for (std::size_t i = 0; i < AllFillMethods().size(); ++i) {
    EXPECT_EQ(ToString(methods[i]), ToString(AllFillMethods()[i]));
  }
  EXPECT_EQ(methods.back(), GapFillMethod::kOcp);
  for (GapFillMethod method : methods) EXPECT_EQ(ParseGapFillMethod(ToString(method)), method);
  // The baseline layer knows neither average nor ocp.
  EXPECT_THROW(ParseFillMethod(ToString(GapFillMethod::kOcp)), InputError);
  EXPECT_THROW(ParseFillMethod(ToString(GapFillMethod::kAverage)), InputError);
  const std::string error = testing::InputErrorOf([] { ParseGapFillMethod("cubic"); });
  EXPECT_NE(error.find("'cubic'"), std::string::npos) << error;
  EXPECT_NE(error.find("pca, average, ocp"), std::string::npos) << error;
}

TEST(GapFill, ABaselineMethodIsFillHsFill) {
  const Recording truth = MakeRigidBodyRecording(5, 60, 100.0, 3);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 1, 20, 34), Hide(gapped, 3, 0, 4)};
  for (GapFillMethod method : AllGapFillMethods()) {
    if (method == GapFillMethod::kOcp || method == GapFillMethod::kAverage) continue;
    GapFillOptions options;
    options.method = method;
    options.baseline.method = FillMethod::kLinear;  // not read
    FillOptions baseline;
    baseline.method = ParseFillMethod(ToString(method));
    Recording by_name, by_fill;
    const FillSummary a = FillGaps(gapped, gaps, options, &by_name);
    const FillSummary b = FillGaps(gapped, gaps, baseline, &by_fill);
    EXPECT_EQ(a.message, b.message);
    EXPECT_EQ(a.method, ToString(method));
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      EXPECT_EQ(a.gaps[i].status, b.gaps[i].status);
      EXPECT_EQ(a.gaps[i].message, b.gaps[i].message);
      const GapFill one = FillGap(gapped, gaps[i], options);
      EXPECT_EQ(one.status, a.gaps[i].status);
      for (std::int64_t f = gaps[i].first; f <= gaps[i].last && one.status == GapStatus::kFilled;
           ++f) {
        EXPECT_EQ(by_name.point(f, gaps[i].marker), by_fill.point(f, gaps[i].marker));
        EXPECT_EQ(one.points.col(f - gaps[i].first), by_fill.point(f, gaps[i].marker));
      }
    }
    // The settings name the method chosen and hold the ocp block.
    EXPECT_EQ(a.ToJson()["settings"]["method"], ToString(method));
    EXPECT_TRUE(a.ToJson()["settings"].contains("ocp"));
  }
}

TEST(GapFill, OcpGapThatNoCandidateFillsKeepsTheCandidatesStatus) {
  // A gap at the start of the recording: spline and rigid skip it; with only those candidates
  // the gap stays missing with the first candidate's status, and the other gap is filled.
  const Recording truth = MakeRigidBodyRecording(5, 60, 100.0, 3);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 1, 0, 9), Hide(gapped, 2, 30, 39)};
  GapFillOptions o;
  o.method = GapFillMethod::kOcp;
  o.ocp.candidates = {FillMethod::kSpline, FillMethod::kRigid};
  o.ocp.optimal_control = false;
  Recording out;
  const FillSummary summary = FillGaps(gapped, gaps, o, &out);
  EXPECT_EQ(summary.gaps_filled, 1);
  EXPECT_EQ(summary.gaps[0].status, GapStatus::kSkippedEdge);
  EXPECT_EQ(summary.gaps[0].message.find("no candidate filled the gap; spline: "), 0u)
      << summary.gaps[0].message;
  EXPECT_FALSE(out.observed(0, 1));
  EXPECT_EQ(summary.gaps[1].status, GapStatus::kFilled);
  EXPECT_EQ(summary.gaps[1].message.find("prior: spline "), 0u) << summary.gaps[1].message;
  EXPECT_EQ(summary.message,
            "2 gaps: 1 kept the prior (optimal_control_off 1), 1 unfillable "
            "(skipped_edge 1)");
  EXPECT_EQ(summary.gaps[0].outcome, GapOutcome::kUnfillable);
  EXPECT_EQ(summary.gaps[1].outcome, GapOutcome::kPrior);
  EXPECT_EQ(summary.gaps[1].prior_reason, "optimal_control_off");
}

TEST(GapFill, AverageIsOcpsPriorBitForBitWhateverOptimalControlSays) {
  const Recording truth = MakeRigidBodyRecording(5, 60, 100.0, 3);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 1, 20, 34), Hide(gapped, 3, 40, 47)};
  GapFillOptions prior;
  prior.method = GapFillMethod::kOcp;
  prior.ocp.optimal_control = false;
  GapFillOptions average;
  average.method = GapFillMethod::kAverage;
  average.ocp.optimal_control = true;  // not read
  Recording by_prior, by_average;
  const FillSummary a = FillGaps(gapped, gaps, prior, &by_prior);
  const FillSummary b = FillGaps(gapped, gaps, average, &by_average);
  EXPECT_EQ(b.method, "average");
  EXPECT_EQ(b.message, "2 gaps: 2 filled by average");
  EXPECT_EQ(b.ToJson()["settings"]["ocp"]["optimal_control"], false);
  const std::vector<GapFill> list = FillGapList(gapped, gaps, average);
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    EXPECT_EQ(b.gaps[i].outcome, GapOutcome::kBaseline);
    EXPECT_TRUE(b.gaps[i].prior_reason.empty());
    EXPECT_EQ(a.gaps[i].message, b.gaps[i].message);  // "prior: rigid …, pca …"
    for (std::int64_t f = gaps[i].first; f <= gaps[i].last; ++f) {
      EXPECT_EQ(by_prior.point(f, gaps[i].marker), by_average.point(f, gaps[i].marker));
      EXPECT_EQ(list[i].points.col(f - gaps[i].first), by_average.point(f, gaps[i].marker));
    }
  }
}

TEST(GapFill, OcpOutcomesAreCountedAsThePerGapEntries) {
  // Two rigid-body gaps with the optimal control on: each gap is solved or keeps the prior for a
  // reason, and the counts are those of the entries.
  const Recording truth = MakeRigidBodyRecording(5, 60, 100.0, 3);
  Recording gapped = truth;
  const std::vector<Gap> gaps = {Hide(gapped, 1, 20, 27), Hide(gapped, 3, 35, 40)};
  GapFillOptions o;
  o.method = GapFillMethod::kOcp;
  Recording out;
  const FillSummary summary = FillGaps(gapped, gaps, o, &out);
  const nlohmann::json j = summary.ToJson();
  std::map<std::string, std::int64_t> by_outcome, by_reason;
  for (const auto& gap : j["gaps"]) {
    ++by_outcome[gap["outcome"].get<std::string>()];
    const bool prior = gap["outcome"] == "prior";
    EXPECT_EQ(prior, !gap["prior_reason"].is_null()) << gap.dump();
    if (prior) ++by_reason[gap["prior_reason"].get<std::string>()];
    EXPECT_EQ(gap["outcome"] == "optimal_control",
              gap["message"].get<std::string>().rfind("optimal control:", 0) == 0)
        << gap.dump();
  }
  for (const char* outcome : {"optimal_control", "prior", "baseline", "unfillable"}) {
    EXPECT_EQ(j["outcomes"][outcome], by_outcome[outcome]) << outcome;
  }
  EXPECT_EQ(j["outcomes"]["prior_by_reason"], nlohmann::json(by_reason));
  EXPECT_EQ(j["outcomes"]["gaps"], 2);
  EXPECT_EQ(by_outcome["optimal_control"] + by_outcome["prior"], 2);
}

TEST(GapFill, BadSettingsAreOneInputErrorNamingTheField) {
  Recording gapped = MakeRigidBodyRecording(5, 40, 100.0, 5);
  const Gap gap = Hide(gapped, 1, 10, 20);
  const auto error = [&](const GapFillOptions& options) {
    Recording out;
    return testing::InputErrorOf([&] { FillGaps(gapped, {gap}, options, &out); });
  };
  GapFillOptions ocp;
  ocp.method = GapFillMethod::kOcp;
  GapFillOptions o = ocp;
  o.ocp.prior_weight = -0.5;
  EXPECT_EQ(error(o).find("ocp.prior_weight"), 0u) << error(o);
  // Whatever the method, every setting is checked.
  o.method = GapFillMethod::kSpline;
  EXPECT_EQ(error(o).find("ocp.prior_weight"), 0u) << error(o);
  o = ocp;
  o.baseline.rigid.donors = 2;
  EXPECT_EQ(error(o).find("rigid.donors: must be ≥ 3 (got 2)"), 0u) << error(o);
  o = ocp;
  o.ocp.padding_seconds = 1.0;  // a window of 100 padding frames in 40 frames
  EXPECT_EQ(error(o).find("ocp.padding_seconds"), 0u) << error(o);
  o = ocp;
  o.ocp.candidates.clear();
  EXPECT_EQ(error(o).find("ocp.candidates"), 0u) << error(o);
  o = ocp;
  o.ocp.network.partners = 0;
  EXPECT_EQ(error(o).find("ocp.network.partners"), 0u) << error(o);
  // The gapped marker is seen with the others in 29 frames, fewer than the network asks for: it
  // has no partners (the candidates fill the gap, the network cannot carry it).
  o = ocp;
  o.ocp.network.min_common_frames = 35;
  EXPECT_NE(error(o).find("no partners"), std::string::npos) << error(o);
}

TEST(GapFill, SettingsJsonIsTheBaselineSettingsWithTheMethodAndOcp) {
  GapFillOptions o;
  o.method = GapFillMethod::kOcp;
  o.baseline.max_gap_seconds = 0.25;
  o.ocp.candidates = {FillMethod::kPca};
  const nlohmann::json j = o.ToJson();
  nlohmann::json expected = o.baseline.ToJson();
  expected["method"] = "ocp";
  expected["ocp"] = o.ocp.ToJson();
  EXPECT_EQ(j, expected);
  EXPECT_EQ(j["ocp"]["candidates"], nlohmann::json::array({"pca"}));
  EXPECT_EQ(j["max_gap_seconds"], 0.25);
}

}  // namespace
}  // namespace moreau::mocap
