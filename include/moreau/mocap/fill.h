// Gap filling: the established methods for missing marker samples, one gap at a time.
//
// Every method fills one Gap (a run of missing frames of one marker, see recording.h) from the
// *input* recording only, so the result never depends on the order in which gaps are filled. A
// gap a method cannot fill keeps its samples missing (NaN, observed = false) and gets a status
// saying why; a filled sample is finite and marked observed.
//
//   linear  straight line between the observed samples at frames first − 1 and last + 1.
//   spline  not-a-knot cubic spline through up to `interpolation.samples_per_side` observed
//           samples on each side (the observed runs adjacent to the gap, at least 2 per side);
//           reproduces any cubic polynomial in time exactly.
//   pchip   monotone piecewise-cubic Hermite interpolation (Fritsch–Carlson: derivatives by the
//           weighted harmonic mean of the neighbouring secant slopes, zero at local extrema, the
//           shape-preserving three-point formula at the ends) through the same samples; never
//           overshoots monotone data.
//   rigid   rigid-body (pattern) fill: the `rigid.donors` markers whose distance to the gapped
//           marker varies least (standard deviation over the frames where both are seen) among
//           those observed throughout the gap and at its bounding frames; the donors' rigid motion
//           (Kabsch least-squares fit) from frame first − 1 and from frame last + 1 carries the
//           gapped marker, and the two estimates are blended linearly across the gap, so the fill
//           meets the observed samples at both ends. Exact for markers on one rigid body.
//   pca     low-rank fill after Gløersen & Federolf (2016, PLoS ONE 11(3): e0152616): positions
//           relative to the mean trajectory of the other markers, normalised by the mean and
//           standard deviation of each coordinate over the complete frames and weighted by
//           w = exp(−d² / (2σ²)) (d: mean distance to the gapped marker, σ = pca.weight_scale_m;
//           the gapped marker itself gets pca.missing_marker_weight); principal components of
//           the complete frames (the fewest whose singular values sum to ≥ explained_fraction of
//           the total); the gapped coordinates are then reconstructed iteratively: start at the
//           mean, project the frame onto the retained components, replace the gapped coordinates
//           by the projection's, repeat until the change is below pca.tolerance. The first
//           iterate is Gløersen & Federolf's reconstruction (to first order in the
//           missing-marker weight); the fixed point is the least-squares fit of the retained
//           components to the observed coordinates, exact for data of rank ≤ the components
//           retained. Gaps at the start or end of the recording can be filled.
//
// These are the baseline fills. The optimal-control fill (ocp_fill.h) is a layer above them that
// receives candidate fills and calls nothing here; gap_fill.h chooses a fill by name and, for
// ocp, computes the candidates with FillGapsMeetingEnds (below) before handing them over.
//
// Adding a method: one FillMethod entry, one row in the name table (fill.cpp), one FillGapX
// function with the signature below, and the same entry in GapFillMethod (gap_fill.h).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "moreau/common/field_list.h"
#include "moreau/common/termination.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

enum class FillMethod { kLinear, kSpline, kPchip, kRigid, kPca };

// "linear", "spline", "pchip", "rigid", "pca".
std::string_view ToString(FillMethod method);
// Throws InputError naming the unknown method and the known ones.
FillMethod ParseFillMethod(std::string_view name);
// Every method, in the order above.
std::vector<FillMethod> AllFillMethods();
// The name table of FillMethod (for field lists).
std::vector<std::pair<FillMethod, std::string_view>> FillMethodNameTable();

// Why a gap was or was not filled.
enum class GapStatus {
  kFilled,         // every sample of the gap is filled
  kSkippedEdge,    // no observed sample on one side (gap at the start or end of the recording)
  kTooLong,        // longer than FillOptions::max_gap_seconds
  kTooFewSamples,  // too few observed samples (per side, or complete frames for pca)
  kNoDonors,       // rigid/pca: too few usable markers observed throughout the gap
  kFailed,         // a numerical failure (message says where)
  kNeverObserved,  // the marker is missing in every frame: nothing to fill it from
};

// "filled", "skipped_edge", "too_long", "too_few_samples", "no_donors", "failed",
// "never_observed".
std::string_view ToString(GapStatus status);
// Throws InputError for an unknown name.
GapStatus ParseGapStatus(std::string_view name);

// Settings of spline and pchip.
struct InterpolationFillOptions {
  // Observed samples taken on each side of the gap (the adjacent observed run, up to this many);
  // ≥ 2. Both methods need at least 2 on each side (else too_few_samples).
  int samples_per_side = 4;
  static const FieldList<InterpolationFillOptions>&
  Fields();  // key, range, unit, help of every field
};

struct RigidFillOptions {
  int donors = 3;  // markers carried rigidly with the gapped one, ≥ 3
  // Frames where a candidate and the gapped marker are both observed, needed to judge how much
  // their distance varies; ≥ 2.
  int min_common_frames = 10;
  static const FieldList<RigidFillOptions>& Fields();  // key, range, unit, help of every field
};

struct PcaFillOptions {
  // Retain the fewest principal components whose singular values sum to ≥ this fraction of the
  // total; in (0, 1].
  double explained_fraction = 0.99;
  // σ of the distance weights w = exp(−d² / (2σ²)), in metres (converted to the recording's
  // units); > 0. Gløersen & Federolf use 200 mm.
  double weight_scale_m = 0.2;
  // Weight of the gapped marker's coordinates, in (0, 1]. Sets how fast the iteration converges
  // (the contraction factor is of order weight²), not where.
  double missing_marker_weight = 0.02;
  // A candidate marker that has missing samples somewhere and lies farther than this multiple of
  // the mean candidate distance is left out (so that it does not remove complete frames); > 0.
  double distal_threshold = 0.5;
  int min_complete_frames = 10;  // frames where every used marker is observed; ≥ 2
  int max_iterations = 200;      // reconstruction iterations, ≥ 1
  // Stop when the largest change of a gapped coordinate, in standard deviations of that
  // coordinate, is ≤ this; > 0.
  double tolerance = 1e-10;
  static const FieldList<PcaFillOptions>& Fields();  // key, range, unit, help of every field
};

struct FillOptions {
  FillMethod method = FillMethod::kSpline;
  // Gaps lasting longer than this (length / rate, seconds) are left missing with status
  // too_long; 0: no limit. ≥ 0.
  double max_gap_seconds = 0.0;
  InterpolationFillOptions interpolation;
  RigidFillOptions rigid;
  PcaFillOptions pca;

  // method, max_gap_seconds, interpolation.*, rigid.*, pca.*.
  static const FieldList<FillOptions>& Fields();
  // Throws InputError(key, reason) for a value out of range.
  void Validate() const;
  nlohmann::json ToJson() const;
};

// What filled a gap, or that nothing did; the summaries count the gaps by it.
enum class GapOutcome {
  kBaseline,        // filled by a baseline method (this file's)
  kOptimalControl,  // filled by the optimal control (ocp_fill.h, outcome kSolved)
  kPrior,           // filled by the optimal-control fill's prior (its weighted candidates), the
                    // optimal control being off or its fill not kept: GapReport::prior_reason
  kUnfillable,      // left missing: GapReport::status says why
};

// The outcome of filling one gap.
struct GapFill {
  GapStatus status = GapStatus::kFilled;
  std::string message;      // why it was not filled, or a note (empty when nothing to say)
  Eigen::Matrix3Xd points;  // 3 × gap.length(), frames first … last; empty unless filled
  // What filled it when filled: kBaseline from this file; gap_fill.h sets kOptimalControl or
  // kPrior for ocp, and for kPrior the reason (GapReport::prior_reason). FillGaps copies both
  // into the gap's GapReport.
  GapOutcome outcome = GapOutcome::kBaseline;
  std::string prior_reason = {};
};

// One method on one gap of `in` (gap consistent with `in`: marker in range, first ≤ last inside
// the recording, every sample missing). The FillGapX functions do not check max_gap_seconds
// or the recording's edges beyond what the method itself needs; FillGap does both (a gap that
// spans every frame is never_observed, whatever the method), then dispatches on options.method.
GapFill FillGapLinear(const Recording& in, const Gap& gap, const FillOptions& options);
GapFill FillGapSpline(const Recording& in, const Gap& gap, const FillOptions& options);
GapFill FillGapPchip(const Recording& in, const Gap& gap, const FillOptions& options);
GapFill FillGapRigid(const Recording& in, const Gap& gap, const FillOptions& options);
GapFill FillGapPca(const Recording& in, const Gap& gap, const FillOptions& options);
GapFill FillGap(const Recording& in, const Gap& gap, const FillOptions& options);

// "baseline", "optimal_control", "prior", "unfillable".
std::string_view ToString(GapOutcome outcome);

struct GapReport {
  int marker = 0;
  std::string label;
  std::int64_t first = 0;  // 0-based, inclusive
  std::int64_t last = 0;
  GapStatus status = GapStatus::kFilled;
  std::string message;
  double seconds = 0.0;  // wall-clock time spent on this gap
  // kUnfillable exactly when status is not kFilled.
  GapOutcome outcome = GapOutcome::kBaseline;
  // Why the prior was kept (outcome kPrior, else empty): "optimal_control_off",
  // "optimal_control_failed" (no converged window; message says how) or "rejected_by_guard" (its
  // fill disagreed with the distance distributions much more than the prior's).
  std::string prior_reason;
  bool filled() const { return status == GapStatus::kFilled; }
};

// The gaps of a summary counted by outcome (every gap in exactly one of the four counts), the
// kept priors by reason and the unfillable gaps by status.
struct GapOutcomeCounts {
  std::int64_t gaps = 0;
  std::int64_t optimal_control = 0;
  std::int64_t prior = 0;
  std::int64_t baseline = 0;
  std::int64_t unfillable = 0;
  std::map<std::string, std::int64_t> prior_by_reason;       // prior_reason → gaps
  std::map<std::string, std::int64_t> unfillable_by_status;  // status name → gaps

  static GapOutcomeCounts Of(const std::vector<GapReport>& gaps);
  // The counts above as keys of one object (the by-reason and by-status counts as objects).
  nlohmann::json ToJson() const;
  // "34 gaps: 6 solved by the optimal control, 28 kept the prior (not_converged 28)";
  // "12 gaps: 10 filled by METHOD, 2 unfillable (too_long 2)"; "0 gaps". Zero counts are left
  // out; METHOD names the baseline method.
  std::string Describe(std::string_view method) const;
};

struct FillSummary {
  Termination termination = Termination::kCompleted;  // always completed: see the gap statuses
  std::string message;          // GapOutcomeCounts::Describe of the gaps: "n gaps: k solved by …"
  std::vector<GapReport> gaps;  // one per input gap, in input order
  std::int64_t gaps_filled = 0;     // every outcome but kUnfillable
  std::int64_t samples_filled = 0;  // marker samples written
  double total_seconds = 0.0;
  // The method tried on every gap, by the name users give it: a FillMethod's, or "ocp" when
  // gap_fill.h ran the optimal-control fill.
  std::string method;
  nlohmann::json settings;  // the options used, as their ToJson() writes them

  bool ok() const { return IsSuccess(termination); }
  // SummaryJson, the counters, "outcomes" (GapOutcomeCounts of the gaps), "gaps" (each with its
  // "outcome" and "prior_reason", null unless the prior was kept) and "settings".
  nlohmann::json ToJson() const;
};

// Fills `gaps` (normally FindGaps(in)) of `in` with options.method and writes the result to
// *out (which may be &in): a copy of `in` with every filled sample set and marked observed.
// Throws InputError for invalid options or a gap that does not match `in` (CheckGaps,
// recording.h), and Interrupted (common/stop.h) before a gap when a stop was requested.
FillSummary FillGaps(const Recording& in, const std::vector<Gap>& gaps, const FillOptions& options,
                     Recording* out);

// FillGaps, each gap filled so that it meets the observed samples that bound it: the gap widened
// by one frame on each side (those two samples hidden) is filled by FillGap, and the fill's
// errors at the two bounding frames, blended linearly across the gap, are removed. A gap at the
// start or end of the recording is widened on its one observed side and shifted by the fill's
// error there (it meets the first or last observed sample without a jump); a gap over the whole
// recording is filled as FillGap does, and so is one whose widened fill fails. These are the
// candidate fills a layer above combines (ocp_fill.h): a method that does not reproduce the samples
// around a gap (pca) would otherwise jump there.
FillSummary FillGapsMeetingEnds(const Recording& in, const std::vector<Gap>& gaps,
                                const FillOptions& options, Recording* out);

}  // namespace moreau::mocap
