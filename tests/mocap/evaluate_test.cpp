#include "moreau/mocap/evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "mocap/synthetic.h"
#include "moreau/common/error.h"

namespace moreau::mocap {
namespace {

using testing::MakeLineRecording;
using testing::MakeRigidBodyRecording;

EvaluationOptions SmallStudy() {
  EvaluationOptions options;
  options.methods = {GapFillMethod::kLinear, GapFillMethod::kSpline, GapFillMethod::kPchip,
                     GapFillMethod::kRigid};
  options.gap_seconds = {0.05, 0.2};
  options.trials = 6;
  options.seed = 42;
  return options;
}

// Bitwise equality of two doubles (NaN equals NaN).
bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void ExpectSameRows(const EvaluationSummary& a, const EvaluationSummary& b) {
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].method, b.rows[i].method);
    EXPECT_EQ(a.rows[i].marker, b.rows[i].marker);
    EXPECT_EQ(a.rows[i].first_frame, b.rows[i].first_frame);
    EXPECT_EQ(a.rows[i].status, b.rows[i].status);
    EXPECT_TRUE(SameBits(a.rows[i].mean_error, b.rows[i].mean_error)) << i;
    EXPECT_TRUE(SameBits(a.rows[i].max_error, b.rows[i].max_error)) << i;
  }
}

TEST(EvaluateFillMethods, ExactMethodsHaveZeroErrorOnTheirKnownAnswers) {
  const Recording line = MakeLineRecording(5, 150, 100.0);
  EvaluationOptions options = SmallStudy();
  options.methods = {GapFillMethod::kLinear, GapFillMethod::kSpline, GapFillMethod::kPchip};
  const EvaluationSummary on_line = EvaluateFillMethods(line, options);
  ASSERT_EQ(on_line.rows.size(), 3u * 2u * 6u);
  for (const EvaluationRow& row : on_line.rows) {
    EXPECT_EQ(row.status, GapStatus::kFilled);
    EXPECT_LT(row.max_error, 1e-9);
    EXPECT_LE(row.mean_error, row.max_error);
  }
  const Recording body = MakeRigidBodyRecording(6, 150, 100.0, 1);
  options.methods = {GapFillMethod::kRigid, GapFillMethod::kLinear};
  const EvaluationSummary on_body = EvaluateFillMethods(body, options);
  for (const EvaluationStatistics& s : on_body.statistics) {
    EXPECT_EQ(s.trials, 6);
    EXPECT_EQ(s.failed, 0);
    EXPECT_LE(s.median, s.percentile_90);
    if (s.method == GapFillMethod::kRigid) {
      EXPECT_LT(s.percentile_90, 1e-8);
    }
  }
}

TEST(EvaluateFillMethods, EveryMethodSeesTheSameMarkerAndPositionAndGapLength) {
  const Recording body = MakeRigidBodyRecording(5, 120, 100.0, 2);
  const EvaluationOptions options = SmallStudy();
  const EvaluationSummary summary = EvaluateFillMethods(body, options);
  const std::size_t methods = options.methods.size();
  for (std::size_t i = 0; i < summary.rows.size(); i += methods) {
    for (std::size_t k = 1; k < methods; ++k) {
      EXPECT_EQ(summary.rows[i + k].marker, summary.rows[i].marker);
      EXPECT_EQ(summary.rows[i + k].first_frame, summary.rows[i].first_frame);
      EXPECT_EQ(summary.rows[i + k].trial, summary.rows[i].trial);
    }
    const std::int64_t frames = summary.rows[i].gap_frames;
    EXPECT_EQ(frames, std::llround(summary.rows[i].gap_seconds * 100.0));
    EXPECT_GE(summary.rows[i].first_frame, options.fill.baseline.interpolation.samples_per_side);
    EXPECT_LE(
        summary.rows[i].first_frame + frames + options.fill.baseline.interpolation.samples_per_side,
        120);
  }
}

TEST(EvaluateFillMethods, ReproducibleFromTheSeedAndIndependentOfTheThreadCount) {
  const Recording body = MakeRigidBodyRecording(6, 120, 100.0, 3);
  EvaluationOptions options = SmallStudy();
  // The established methods; ocp has its own thread-count test (MocapOcpFill.Evaluation...).
  options.methods = {GapFillMethod::kLinear, GapFillMethod::kSpline, GapFillMethod::kPchip,
                     GapFillMethod::kRigid, GapFillMethod::kPca};
  options.threads = 1;
  const EvaluationSummary one = EvaluateFillMethods(body, options);
  options.threads = 3;
  const EvaluationSummary three = EvaluateFillMethods(body, options);
  ExpectSameRows(one, three);
  options.threads = 2;
  ExpectSameRows(one, EvaluateFillMethods(body, options));

  options.seed = 43;
  const EvaluationSummary other = EvaluateFillMethods(body, options);
  bool differs = false;
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    differs = differs || one.rows[i].marker != other.rows[i].marker ||
              one.rows[i].first_frame != other.rows[i].first_frame;
  }
  EXPECT_TRUE(differs);
}

TEST(EvaluateFillMethods, PcaOnAFullSizeBodyIsIndependentOfTheThreadCount) {
  // 55 markers: products large enough for Eigen's own OpenMP paths, were they used.
  const Recording body = testing::MakeWalkingRecording(340, 200.0, 5);
  EvaluationOptions options;
  options.methods = {GapFillMethod::kPca, GapFillMethod::kRigid};
  options.gap_seconds = {0.1, 0.5};
  options.trials = 4;
  options.threads = 1;
  const EvaluationSummary one = EvaluateFillMethods(body, options);
  options.threads = 3;
  ExpectSameRows(one, EvaluateFillMethods(body, options));
  for (const EvaluationRow& row : one.rows) EXPECT_EQ(row.status, GapStatus::kFilled);
}

TEST(EvaluateFillMethods, FailedFillsAreCountedAndWrittenAsNull) {
  // Three markers: rigid never has three donors.
  const Recording line = MakeLineRecording(3, 100, 100.0);
  EvaluationOptions options = SmallStudy();
  options.methods = {GapFillMethod::kRigid};
  const EvaluationSummary summary = EvaluateFillMethods(line, options);
  for (const EvaluationStatistics& s : summary.statistics) {
    EXPECT_EQ(s.failed, s.trials);
    EXPECT_TRUE(std::isnan(s.mean));
  }
  const nlohmann::json j = summary.ToJson();
  EXPECT_TRUE(j["statistics"][0]["mean_error"].is_null());
  EXPECT_EQ(j["rows"][0]["status"], "no_donors");
  EXPECT_EQ(j["settings"]["methods"][0], "rigid");
}

TEST(EvaluateFillMethods, PercentileInterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(Percentile({4.0, 1.0, 3.0, 2.0}, 50.0), 2.5);
  EXPECT_DOUBLE_EQ(Percentile({4.0, 1.0, 3.0, 2.0}, 90.0), 3.7);
  EXPECT_DOUBLE_EQ(Percentile({5.0}, 90.0), 5.0);
  EXPECT_TRUE(std::isnan(Percentile({}, 50.0)));
}

TEST(EvaluateFillMethods, BadInputIsAnInputErrorNamingTheField) {
  const Recording line = MakeLineRecording(3, 40, 100.0);
  const auto message = [&](const EvaluationOptions& options, const Recording& r) {
    try {
      EvaluateFillMethods(r, options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EvaluationOptions options = SmallStudy();
  options.trials = 0;
  EXPECT_NE(message(options, line).find("trials: must be ≥ 1 (got 0)"), std::string::npos);
  options = SmallStudy();
  options.gap_seconds = {0.5};  // 50 frames do not fit in 40
  EXPECT_NE(message(options, line).find("evaluation.gap_seconds"), std::string::npos);
  options = SmallStudy();
  options.fill.baseline.rigid.donors = 1;
  EXPECT_NE(message(options, line).find("rigid.donors: must be ≥ 3 (got 1)"), std::string::npos);
  Recording incomplete = line;
  incomplete.ClearPoint(3, 1);
  EXPECT_NE(message(SmallStudy(), incomplete).find("complete"), std::string::npos);
}

}  // namespace
}  // namespace moreau::mocap
