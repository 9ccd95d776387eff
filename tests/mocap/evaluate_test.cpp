#include "moreau/mocap/evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "mocap/synthetic.h"
#include "moreau/common/error.h"
#include "moreau/mocap/complete_part.h"

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

TEST(EvaluateFillMethods, HidesOneSegmentTogetherAndEveryMethodFillsEachOfItsMarkers) {
  // The walking body: 15 segments of 3 to 5 markers. Three markers hidden together are one
  // segment (their mutual distances do not vary), share their frames, and each has its row.
  const Recording body = testing::MakeWalkingRecording(240, 120.0, 5);
  EvaluationOptions options;
  options.methods = {GapFillMethod::kSpline, GapFillMethod::kPca};
  options.gap_seconds = {0.1};
  options.trials = 4;
  options.markers_per_gap = 3;
  const EvaluationSummary summary = EvaluateFillMethods(body, options);
  ASSERT_EQ(summary.rows.size(), 4u * 2u * 3u);
  for (std::size_t i = 0; i < summary.rows.size(); i += 6) {
    for (std::size_t k = 0; k < 6; ++k) {
      const EvaluationRow& row = summary.rows[i + k];
      EXPECT_EQ(row.method, options.methods[k / 3]);
      EXPECT_EQ(row.marker, summary.rows[i + k % 3].marker);
      EXPECT_EQ(row.first_frame, summary.rows[i].first_frame);
      EXPECT_EQ(row.status, GapStatus::kFilled);
      EXPECT_TRUE(std::isfinite(row.acceleration_error) && std::isfinite(row.distance_z));
      EXPECT_LE(row.p90_error, row.max_error);
    }
    const int a = summary.rows[i].marker, b = summary.rows[i + 1].marker,
              c = summary.rows[i + 2].marker;
    EXPECT_TRUE(a != b && b != c && a != c);
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{a, c}}) {
      EXPECT_LT(MarkerDistanceStatistics(body, p, q).sd, 1e-9) << p << " " << q;
    }
  }
  for (const EvaluationStatistics& s : summary.statistics) {
    EXPECT_EQ(s.trials, 4);
    EXPECT_EQ(s.gaps, 12);
    double sum = 0.0;
    for (const EvaluationRow& row : summary.rows) {
      if (row.method == s.method) sum += row.acceleration_error;
    }
    EXPECT_NEAR(s.acceleration_error.mean, sum / 12.0, 1e-12 * sum);
  }
}

TEST(EvaluateFillMethods, NoFillSeesAnotherHiddenMarkersSamples) {
  // Four markers on one rigid body: with one hidden, rigid has its three donors and is exact;
  // with two hidden, two markers are left and rigid has no donors for either.
  const Recording body = MakeRigidBodyRecording(4, 120, 100.0, 6);
  EvaluationOptions options = SmallStudy();
  options.methods = {GapFillMethod::kRigid, GapFillMethod::kLinear};
  for (const EvaluationRow& row : EvaluateFillMethods(body, options).rows) {
    EXPECT_EQ(row.status, GapStatus::kFilled);
    if (row.method == GapFillMethod::kRigid) {
      EXPECT_LT(row.max_error, 1e-8);
    }
  }
  options.markers_per_gap = 2;
  const EvaluationSummary two = EvaluateFillMethods(body, options);
  ASSERT_EQ(two.rows.size(), 2u * 6u * 2u * 2u);
  for (const EvaluationRow& row : two.rows) {
    EXPECT_EQ(row.status,
              row.method == GapFillMethod::kRigid ? GapStatus::kNoDonors : GapStatus::kFilled);
  }
}

TEST(EvaluateFillMethods, GapsAtTheStartTheEndOrAnywhere) {
  const Recording body = MakeRigidBodyRecording(6, 120, 100.0, 7);
  EvaluationOptions options = SmallStudy();
  options.methods = {GapFillMethod::kLinear, GapFillMethod::kPca};
  options.placement = GapPlacement::kStart;
  const EvaluationSummary start = EvaluateFillMethods(body, options);
  options.placement = GapPlacement::kEnd;
  const EvaluationSummary end = EvaluateFillMethods(body, options);
  options.placement = GapPlacement::kAny;
  options.threads = 1;
  const EvaluationSummary any = EvaluateFillMethods(body, options);
  options.threads = 3;
  ExpectSameRows(any, EvaluateFillMethods(body, options));
  const EvaluationSummary interior = EvaluateFillMethods(body, SmallStudy());
  for (std::size_t i = 0; i < start.rows.size(); ++i) {
    const EvaluationRow &s = start.rows[i], &e = end.rows[i];
    EXPECT_EQ(s.first_frame, 0);
    EXPECT_EQ(e.first_frame + e.gap_frames, 120);
    EXPECT_EQ(s.marker, interior.rows[i / 2 * 4].marker);  // the same draws, placed elsewhere
    EXPECT_GE(any.rows[i].first_frame, 0);
    EXPECT_LE(any.rows[i].first_frame + any.rows[i].gap_frames, 120);
    if (s.method == GapFillMethod::kLinear) {
      EXPECT_EQ(s.status, GapStatus::kSkippedEdge);
      EXPECT_EQ(e.status, GapStatus::kSkippedEdge);
      continue;
    }
    EXPECT_EQ(s.status, GapStatus::kFilled);
    EXPECT_TRUE(std::isnan(s.velocity_jump_start) && std::isfinite(s.velocity_jump_end));
    EXPECT_TRUE(std::isfinite(e.velocity_jump_start) && std::isnan(e.velocity_jump_end));
    EXPECT_EQ(s.velocity_jump(), s.velocity_jump_end);
    EXPECT_TRUE(std::isfinite(s.velocity_error) && std::isfinite(e.acceleration_error));
  }
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
  options = SmallStudy();
  options.filter_hz = 50.0;  // the Nyquist frequency of 100 Hz
  EXPECT_NE(message(options, line).find("evaluation.filter_hz: must be below"), std::string::npos);
  options = SmallStudy();
  options.markers_per_gap = 4;
  EXPECT_NE(message(options, line).find("evaluation.markers_per_gap"), std::string::npos);
  options = SmallStudy();
  options.placement = GapPlacement::kStart;
  options.gap_seconds = {0.37};  // 37 frames and 4 observed after them: 41 > 40
  EXPECT_NE(message(options, line).find("on one side"), std::string::npos);
  Recording incomplete = line;
  incomplete.ClearPoint(3, 1);
  options = SmallStudy();
  options.complete_part = false;
  EXPECT_NE(message(options, incomplete).find("complete_part is false"), std::string::npos);
  // Every marker has a hole somewhere: no part of 28 frames holds two complete markers.
  for (int m = 0; m < incomplete.markers(); ++m) incomplete.ClearPoint(20, m);
  EXPECT_NE(message(SmallStudy(), incomplete).find("no 28 frames hold 2 complete markers"),
            std::string::npos)
      << message(SmallStudy(), incomplete);
}

TEST(EvaluateFillMethods, ARecordingWithHolesIsEvaluatedOnItsCompletePart) {
  // Marker 1 is missing over frames 0–9 and marker 4 at frame 140: the part with the most
  // samples is frames 10–139 with all six markers (780 samples against 600 for the whole take
  // with four markers and 700 for either one-sided range with five).
  Recording holes = MakeRigidBodyRecording(6, 150, 100.0, 3);
  for (std::int64_t f = 0; f < 10; ++f) holes.ClearPoint(f, 1);
  holes.ClearPoint(140, 4);
  const CompletePart part = FindCompletePart(holes, 28);
  EXPECT_EQ(part.first, 10);
  EXPECT_EQ(part.frames, 130);
  EXPECT_EQ(part.markers, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  // A longer minimum leaves the shorter ranges out: the whole take with the four complete markers.
  const CompletePart whole = FindCompletePart(holes, 145);
  EXPECT_EQ(whole.first, 0);
  EXPECT_EQ(whole.frames, 150);
  EXPECT_EQ(whole.markers, (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(whole.ToJson(holes)["dropped"], nlohmann::json({"M1", "M4"}));

  const Recording extracted = ExtractPart(holes, part);
  EXPECT_EQ(extracted.frames(), 130);
  EXPECT_EQ(extracted.first_frame(), holes.first_frame() + 10);
  EXPECT_EQ(extracted.point(0, 1), holes.point(10, 1));
  const EvaluationOptions options = SmallStudy();
  const EvaluationSummary on_holes = EvaluateFillMethods(holes, options);
  EvaluationSummary on_part = EvaluateFillMethods(extracted, options);
  EXPECT_TRUE(on_part.complete_part.is_null());
  EXPECT_EQ(on_holes.complete_part["first_frame"], 10);
  // The rows are the part's, naming the input's markers and frames.
  for (EvaluationRow& row : on_part.rows) {
    row.marker = part.markers[static_cast<std::size_t>(row.marker)];
    row.first_frame += part.first;
  }
  ExpectSameRows(on_holes, on_part);
  EXPECT_EQ(on_holes.method_seconds.size(), options.methods.size());
}

}  // namespace
}  // namespace moreau::mocap
