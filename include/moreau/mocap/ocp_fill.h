// The optimal-control gap fill: a layer above the baseline fills (fill.h). It receives candidate
// fills of the gaps (any recordings that hold them; gap_fill.h passes the baseline fills named by
// `candidates`, computed by FillGapsMeetingEnds) and never calls a baseline fill itself. From
// them it forms each gap's prior (Tits et al. 2018) and, optionally, refines it by optimal
// control of a mass–spring–damper network (the thesis' regularised Hamiltonian, Symplectic
// Pontryagin scheme, Newton and continuation, in include/moreau/control/).
// docs/mocap.md explains the method, every default and the measurements behind them.
//
// The prior of a gap: the candidates' average with weights (E_c + 10⁻³)^(−weight_exponent),
// E_c the mean squared z-score of the candidate's distances to the marker's spring partners seen
// at the gap's frames, z = (d − mean) / max(spread, bound margin). With optimal_control off the
// prior is the fill (outcome kPrior); with it on:
//
// Per group of gaps (gaps whose padded windows overlap in time and whose markers are the same
// or joined by a spring are solved together) one window is solved:
//   * free nodes: the group's hidden markers; anchors: their network partners, fixed nodes moving
//     along their observed (or candidate-filled) trajectories (C¹ cubic Hermite in time);
//   * springs: the network's springs of the free nodes, rest-length bounds from the observed
//     distance range (network_from_recording.h), the rest lengths are the controls;
//   * tracking: observed samples with weight `observed_weight`; inside a gap the prior with
//     weight `prior_weight`;
//   * the window spans the group's gaps plus `padding_seconds` on each side, so the cost grows
//     with the gaps, not with the recording.
// Units inside the solver: length in network.length_scale, time in frames, weights and γ per
// frame (docs/mocap.md).
// A window that fails to converge is retried with stiffness continuation from a smooth γ, then
// with fewer springs to anchors (retry_anchor_springs), then, if a free marker is hidden at the
// window's first or last frame (a gap at an edge of the take: the prior is an extrapolation),
// with that gap's prior weighted like the observations (min(prior_weight, observed_weight)); if
// that fails too, or a solved gap disagrees with the partners' distance distributions much more
// than the prior (guard_ratio), the gap is filled by the prior (outcome kFallback).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/termination.h"
#include "moreau/control/newton.h"
#include "moreau/mocap/fill.h"
#include "moreau/mocap/network_from_recording.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

struct OcpFillOptions {
  MarkerNetworkOptions network;  // how the network is built from the recording
  double padding_seconds = 0.1;  // observed frames tracked on each side of a gap (>= 0)
  int min_padding_frames = 3;    // at least this many padding frames (>= 1)
  int anchor_springs = 0;        // per free node, springs to anchors: the most rigid ones (0: all)
  double observed_weight = 1.0;  // μ_x w on observed samples (per frame, lengths in ℓ; > 0)
  double prior_weight = 10.0;    // w on the prior inside a gap (>= 0; 0: no prior)
  double gamma =
      0.01;  // target γ of the regularised Hamiltonian (per frame, like the weights; > 0)
  double gamma_start = 0.01;     // first solve at this γ, then continuation (>= gamma)
  double max_step_frames = 1.0;  // Δt <= this many frames, and √k Δt <= 0.5, c Δt <= 1 for the
                                 // window's fastest rates k, c (docs/mocap.md) (> 0)
  double stiffness_start = 0.25;   // retry: continuation in κ, ξ from this scale (0, 1]
  double retry_gamma_start = 1.0;  // retry: continuation in γ from here (>= gamma_start)
  // When both fail: the window again with only each free marker's this many most rigid springs
  // to anchors (>= 0; 0: no such attempt; none either when anchor_springs is already at most
  // this). Then the edge attempt (above), if the window has an edge gap.
  int retry_anchor_springs = 4;
  double guard_ratio = 1.5;        // keep the solved fill only if its distance disagreement E is
                                   // <= guard_ratio E_prior + 1 (E_prior: the prior's) (>= 1)
  // The baseline fills (fill.h) that gap_fill.h computes for the gaps and passes to FillGapsOcp
  // as candidates, at least one (FillGapsOcp itself takes the candidates it is given).
  std::vector<FillMethod> candidates = {FillMethod::kRigid, FillMethod::kPca};
  // Exponent p of the candidate weights 1 / (E_c + 10⁻³)^p (>= 0; 0: plain average).
  double weight_exponent = 2.0;
  // Rest-length bounds of a window centred on the prior: the range of the spring's length along
  // the prior over the window, widened by the network's margin rule and kept inside the bounds
  // observed over the recording (false: the recording's bounds).
  bool prior_bounds = false;
  // true: the network tracks the prior and the observed samples (the optimal control problem);
  // false: the gaps are filled with the prior (the weighted candidate average), outcome kPrior.
  // On by default: "ocp" is the optimal-control fill. Off gives the Tits-weighted prior alone,
  // about as accurate on the measured recordings at a fraction of the time (docs/mocap.md).
  bool optimal_control = true;
  control::NewtonOptions newton;  // every Newton solve (tolerance in solver units)

  // Every field: network.* (but its springs), newton.*, the weights, candidates, ….
  static const FieldList<OcpFillOptions>& Fields();
  // Throws InputError(key, reason) for a value out of range.
  void Validate() const;
  nlohmann::json ToJson() const;
};

// A fill that the optimal control uses as prior, warm start and fallback: a recording with the
// same markers and frames in which (at least) the gaps to fill hold finite positions.
struct CandidateFill {
  std::string method;  // its name in the reports, e.g. "rigid"
  const Recording* recording = nullptr;
};

// How a gap was filled.
enum class OcpOutcome {
  kSolved,    // by the optimal control
  kPrior,     // by the prior, the optimal control being off (optimal_control = false)
  kFallback,  // by the prior, the optimal control having failed or been rejected by the guard
};

// "ocp", "prior", "fallback".
std::string_view ToString(OcpOutcome outcome);
// Throws InputError for an unknown name.
OcpOutcome ParseOcpOutcome(std::string_view name);

// What happened to one gap.
struct OcpGapReport {
  int marker = 0;
  std::string label;
  std::int64_t first = 0;  // gap frames (0-based, inclusive)
  std::int64_t last = 0;
  std::int64_t window_first = 0;  // frames of the solved window
  std::int64_t window_last = 0;
  int window = 0;             // index of the window (gaps solved together share it)
  int free_nodes = 0;         // hidden markers solved together
  int anchors = 0;            // moving fixed nodes
  int springs = 0;            // springs in the window's network
  int steps = 0;              // N of the Symplectic Pontryagin scheme
  int newton_iterations = 0;  // all Newton solves of the window
  double residual = 0.0;      // ‖F‖_∞ of the final iterate (solver units)
  double disagreement = 0.0;  // mean squared z-score of the solved fill's partner distances
  double seconds = 0.0;       // wall-clock time of the window
  Termination termination = Termination::kConverged;
  OcpOutcome outcome = OcpOutcome::kSolved;  // "status" in ToJson (and "fallback_method":
                                             // "prior" for kFallback)
  std::string message;
  std::vector<double> candidate_weights;  // prior weight of each candidate (sum 1; 0 for one
                                          // that does not fill the gap)
  nlohmann::json ToJson() const;
};

struct OcpFillSummary {
  Termination termination = Termination::kConverged;  // kConverged unless a window fell back
  std::string message;
  std::vector<OcpGapReport> gaps;  // one per input gap, in input order
  int windows = 0;
  int fallbacks = 0;
  double network_seconds = 0.0;  // building the network
  double prior_seconds = 0.0;    // the candidates' tracks and the priors
  double solve_seconds = 0.0;    // all windows
  double total_seconds = 0.0;
  MarkerNetwork network;             // the network used
  std::vector<std::string> methods;  // candidate methods, in candidate order
  OcpFillOptions settings;
  bool ok() const { return IsSuccess(termination); }
  // SummaryJson + counters, "network" (MarkerNetwork::ToJson), "gaps" and "settings".
  nlohmann::json ToJson(const Recording& recording) const;
};

// Fills `gaps` of `in` into `out` (a copy of `in` whose gap samples are set; other samples are
// untouched) from `candidates`, the prior/fallback fills (at least one); a candidate without
// finite samples in a gap is not used for that gap. options.candidates is not read. Throws
// InputError for invalid options, no candidate, a gap that does not match `in` (CheckGaps,
// recording.h), a padding longer than the recording, a gap of a marker without springs, a
// candidate of another shape, or a gap that no candidate fills.
OcpFillSummary FillGapsOcp(const Recording& in, const std::vector<Gap>& gaps,
                           const std::vector<CandidateFill>& candidates,
                           const OcpFillOptions& options, Recording* out);

}  // namespace moreau::mocap
