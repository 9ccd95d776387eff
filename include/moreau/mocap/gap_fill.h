// Gap filling by a method the user names (moreau fill-gaps and evaluate-gaps, Python's fill_gaps
// and evaluate): one of the baseline fills (fill.h), average (the weighted candidate average of
// ocp_fill.h on its own) or ocp, the optimal-control fill (ocp_fill.h). This is where the two
// layers meet. For a baseline method the fill is fill.h's; for average and ocp the baseline fills
// named by ocp.candidates are computed for the gaps by FillGapsMeetingEnds and handed to
// FillGapsOcp as its candidates (average: with ocp.optimal_control off, whatever its value). A gap
// that no candidate fills is left missing with the first candidate's status that failed ("no
// candidate filled the gap; rigid: …"), and the others are solved without it.
#pragma once

#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/mocap/fill.h"
#include "moreau/mocap/ocp_fill.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

// The baseline methods, in FillMethod's order, then the candidate average, then ocp.
enum class GapFillMethod { kLinear, kSpline, kPchip, kRigid, kPca, kAverage, kOcp };

// The FillMethod names ("linear", "spline", "pchip", "rigid", "pca"), "average" and "ocp".
std::string_view ToString(GapFillMethod method);
// Throws InputError "unknown fill method 'NAME' (expected one of linear, …, ocp)".
GapFillMethod ParseGapFillMethod(std::string_view name);
// Every method, in the order above.
std::vector<GapFillMethod> AllGapFillMethods();
// The name table of GapFillMethod (for field lists).
std::vector<std::pair<GapFillMethod, std::string_view>> GapFillMethodNameTable();

// The settings of a fill by any method: the method, the baseline fills' settings and the
// optimal-control fill's. A caller that needs both kinds of setting holds this one struct.
struct GapFillOptions {
  GapFillMethod method = GapFillMethod::kSpline;
  // The baseline fills' settings: those of `method`, or of ocp's candidates. baseline.method is
  // not read (`method` and ocp.candidates choose).
  FillOptions baseline;
  OcpFillOptions ocp;  // read when method is average (but its optimal_control) or ocp

  // method, max_gap_seconds, interpolation.*, rigid.*, pca.* (baseline's, but its method) and
  // ocp.*.
  static const FieldList<GapFillOptions>& Fields();
  // Throws InputError(key, reason) for any field out of range, whatever the method.
  void Validate() const;
  // baseline.ToJson() with "method" from `method`, and "ocp": ocp.ToJson().
  nlohmann::json ToJson() const;
};

// Fills `gaps` of `in` with options.method into *out (which may be &in), as FillGaps (fill.h)
// does; for ocp each filled gap's message says how: "optimal control: window …; prior rigid
// 0.71, pca 0.29", "prior: rigid 0.71, pca 0.29" (optimal control off) or "prior (rigid …): why"
// (the optimal control failed or was rejected); for average "prior: rigid 0.71, pca 0.29". Each
// GapReport's outcome says what filled the gap: kBaseline for a baseline method and for average;
// for ocp kOptimalControl (OcpOutcome kSolved) or kPrior with
// prior_reason "optimal_control_off" (kPrior), "optimal_control_failed" (kFallback, the window
// did not converge or was rejected) or "rejected_by_guard" (kFallback, converged but turned down
// by the guard); kUnfillable when nothing filled it. Throws InputError as FillGaps and FillGapsOcp
// do, and Interrupted (common/stop.h) as FillGaps and SolveNewton do after a stop request.
FillSummary FillGaps(const Recording& in, const std::vector<Gap>& gaps,
                     const GapFillOptions& options, Recording* out);

// One gap: FillGap (fill.h) for a baseline method; for ocp the gap alone through FillGaps.
GapFill FillGap(const Recording& in, const Gap& gap, const GapFillOptions& options);

// Every gap of `gaps` (each consistent with `in`, as FillGap asks), one GapFill per gap in input
// order, without writing a recording: FillGap per gap for a baseline method; for ocp the gaps
// together, as FillGaps solves them (gaps close in time and joined by springs share a window).
// The fills use only what `in` holds: the samples of every gap are missing while any is filled.
// For one gap this is FillGap, bit for bit.
std::vector<GapFill> FillGapList(const Recording& in, const std::vector<Gap>& gaps,
                                 const GapFillOptions& options);

}  // namespace moreau::mocap
