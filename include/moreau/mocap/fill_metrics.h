// The measures of a filled gap that a biomechanist reads: how far the fill is from the truth
// (positions, and velocities and accelerations after the usual low-pass filter), how smoothly it
// joins the observed samples, and how well it keeps the marker's distances to its most rigid
// partners. `moreau evaluate-gaps` reports them per hidden gap (evaluate.h); any caller that knows
// the truth of a filled gap can call them.
//
// Conventions: `filled` is a recording whose gap holds the fill (finite samples at the gap's
// frames of gap.marker); `truth` has the same markers and frames; lengths are in the recordings'
// units, times in seconds (rate: frames per second). A measure that cannot be formed (a sample it
// needs is missing or non-finite) is NaN.
//
// The filter is Winter's (Biomechanics and Motor Control of Human Movement, 4th ed., 2009,
// §3.4.4): a 2nd-order low-pass Butterworth section run forward then backward, a 4th-order filter
// with zero phase lag. Its cutoff is corrected for the double pass as Robertson & Dowling (2003,
// J. Electromyogr. Kinesiol. 13: 569–573) state Winter's correction: the section's pre-warped
// cutoff is Ω = tan(π f_c / f_s) / C with C = (2^(1/2) − 1)^(1/4) ≈ 0.802, so that the double
// pass has gain exactly 1/√2 (−3 dB) at f_c; its gain at any f is
// G(f) = 1 / (1 + (tan(π f / f_s) / Ω)^4) (ZeroLagLowPassGain).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "moreau/mocap/recording.h"

namespace moreau::mocap {

// The p-th percentile (p in [0, 100]) of `values` by linear interpolation between the order
// statistics (NaN for none).
double Percentile(std::vector<double> values, double p);

// One 2nd-order section y[n] = b0 x[n] + b1 x[n−1] + b2 x[n−2] − a1 y[n−1] − a2 y[n−2].
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
};

// Winter's cutoff correction for a filter run `passes` times: C = (2^(1/passes) − 1)^(1/4)
// (0.802 for 2). passes ≥ 1.
double WinterCorrection(int passes);

// The low-pass Butterworth section (bilinear transform, pre-warped) whose forward-backward double
// pass has its −3 dB point at cutoff_hz: Ω = tan(π cutoff / rate) / WinterCorrection(2),
// b0 = Ω² / (1 + √2 Ω + Ω²), b1 = 2 b0, b2 = b0, a1 = 2 (Ω² − 1) / (1 + √2 Ω + Ω²),
// a2 = (1 − √2 Ω + Ω²) / (1 + √2 Ω + Ω²). Unit gain at 0 Hz. Throws InputError("filter_hz", …)
// unless 0 < cutoff_hz < rate_hz / 2 (the Nyquist frequency).
Biquad ZeroLagLowPassSection(double rate_hz, double cutoff_hz);

// The exact gain of the double pass at frequency_hz (0 ≤ f < rate/2): the section's squared
// magnitude response, 1 / (1 + (tan(π f / rate) / Ω)^4). Its phase is zero at every f.
double ZeroLagLowPassGain(double frequency_hz, double rate_hz, double cutoff_hz);

// Frames of padding ZeroLagLowPass adds at each end: ⌈3 rate / cutoff⌉ (three periods of the
// cutoff; the section's response decays by e^(−3π) ≈ 10⁻⁴ over one period), at most n − 1.
std::int64_t LowPassPadding(std::int64_t n, double rate_hz, double cutoff_hz);

// Each row of `samples` (d × n, n ≥ 2) filtered forward then backward by ZeroLagLowPassSection.
// The ends: each row is extended by odd reflection, x[−k] = 2 x[0] − x[k] and
// x[n−1+k] = 2 x[n−1] − x[n−1−k] for k = 1 … LowPassPadding(n), which continues the value and the
// slope at each end; each pass starts at rest at its first (padded) sample (past inputs and
// outputs equal to it). The padding is dropped from the result (d × n). Throws InputError as
// ZeroLagLowPassSection, or for n < 2.
Eigen::MatrixXd ZeroLagLowPass(const Eigen::MatrixXd& samples, double rate_hz, double cutoff_hz);

// A trajectory after the low-pass filter and its derivatives, 3 × n each.
struct FilteredKinematics {
  Eigen::Matrix3Xd position;
  Eigen::Matrix3Xd velocity;      // units per second
  Eigen::Matrix3Xd acceleration;  // units per second²
};

// `samples` (3 × n, frames 1/rate apart, n ≥ 2) filtered as ZeroLagLowPass does, then
// differentiated by central differences, v[i] = (x[i+1] − x[i−1]) rate / 2 and
// a[i] = (x[i+1] − 2 x[i] + x[i−1]) rate², at every frame; at the two ends the differences use the
// filtered padding. The odd reflection is antisymmetric about an end, so the acceleration there
// tends to 0 (the ends' accelerations are lost; FilteredDerivativeErrorInGap filters a window
// wide enough that the gap lies in its interior unless the gap touches the recording's edge).
FilteredKinematics FilterAndDifferentiate(const Eigen::Matrix3Xd& samples, double rate_hz,
                                          double cutoff_hz);

// The samples of `marker` at frames first … last (3 × (last − first + 1)); NaN where missing.
Eigen::Matrix3Xd MarkerTrack(const Recording& recording, int marker, std::int64_t first,
                             std::int64_t last);

// The Euclidean distance between the fill and the truth at each gap frame: its mean, 90th
// percentile (Percentile) and maximum.
struct PositionError {
  double mean = 0.0;
  double p90 = 0.0;
  double max = 0.0;
};
PositionError PositionErrorInGap(const Recording& truth, const Recording& filled, const Gap& gap);

// Velocity and acceleration errors after the filter: the marker's track over the window
// [gap.first − P, gap.last + P] ∩ [0, frames − 1], P = ⌈rate / cutoff_hz⌉, taken from `filled`
// (the fill inside the gap, what `filled` holds around it) and from `truth`, each filtered and
// differentiated by FilterAndDifferentiate; the errors are the Euclidean norms of the
// differences at the gap's frames, their mean (and maximum). Where `filled` equals the truth
// outside the gap (the evaluation) the filter being linear, this is the filtered fill error alone,
// and P frames are more than the filter needs to forget the window's ends. NaN when a sample of
// the window is missing in either recording.
struct DerivativeError {
  double velocity_mean = 0.0;      // units / s
  double velocity_max = 0.0;       // units / s
  double acceleration_mean = 0.0;  // units / s²
  double acceleration_max = 0.0;   // units / s²
};
DerivativeError FilteredDerivativeErrorInGap(const Recording& truth, const Recording& filled,
                                             const Gap& gap, double cutoff_hz);

// The velocity jump at each end of the gap, unfiltered, in units / s:
//   start = ‖(x[first] − x[first − 1]) − (x[first − 1] − x[first − 2])‖ rate,
//   end   = ‖(x[last + 1] − x[last]) − (x[last + 2] − x[last + 1])‖ rate,
// the change between the velocity entering the fill (a one-sided difference between the fill's
// first frame and the last frame before the gap; leaving it: between the fill's last frame and
// the first frame after) and the velocity of the samples just outside (the one-sided difference
// of the two frames before the gap; after it). A fill that meets the observed samples with their
// own slope has a jump of the order of the true acceleration / rate; a fill that does not
// meet them (an offset of δ) has a jump of about δ · rate. NaN at an end with fewer than two
// finite samples outside the gap (a gap at the recording's start or end).
struct VelocityJump {
  double start = 0.0;
  double end = 0.0;
};
VelocityJump VelocityJumpAtGapEnds(const Recording& filled, const Gap& gap);

// The distance between markers a and b over the frames where both are observed in `observed`:
// its mean and standard deviation (population, two passes), and the number of such frames (mean
// and sd NaN when none).
struct DistanceStatistics {
  double mean = 0.0;  // units
  double sd = 0.0;    // units
  std::int64_t frames = 0;
};
DistanceStatistics MarkerDistanceStatistics(const Recording& observed, int a, int b);

// The markers whose distance to `marker` varies least: per other marker, the mean and the
// standard deviation (population) of the distance over the frames where both are observed in
// `observed` (which has the gap missing, so that the statistics are those of the observed
// distribution), the `count` with the smallest standard deviation (ties by index) among those
// seen together with `marker` on at least `min_frames` frames. Fewer when fewer qualify.
struct RigidPartners {
  std::vector<int> markers;
  std::vector<double> mean;  // units
  std::vector<double> sd;    // units
};
RigidPartners FindRigidPartners(const Recording& observed, int marker, int count = 3,
                                int min_frames = 2);

// How far the fill takes the distances to the partners from their observed distribution, over
// the gap's frames t and the partners p whose position in `filled` is finite at t:
//   mean = mean over (t, p) of |d_p(t) − mean_p|                          (units),
//   z    = mean over (t, p) of |d_p(t) − mean_p| / max(sd_p, 10⁻⁶ mean_p)  (dimensionless),
// d_p(t) the distance between the marker and partner p in `filled` (a hidden partner counts with
// its own fill). NaN when no partner has a finite position at a gap frame.
struct DistanceDeviation {
  double mean = 0.0;  // units
  double z = 0.0;     // standard deviations
};
DistanceDeviation PartnerDistanceDeviation(const Recording& filled, const Gap& gap,
                                           const RigidPartners& partners);

// Every measure above of one filled gap (evaluate-gaps' rows, fill-gaps' report where the truth
// is known); the derivative errors are NaN unless cutoff_hz is below rate / 2.
struct FilledGapMeasures {
  PositionError position;
  DerivativeError derivative;
  VelocityJump jump;
  DistanceDeviation distance;
};
FilledGapMeasures MeasureFilledGap(const Recording& truth, const Recording& filled, const Gap& gap,
                                   const RigidPartners& partners, double cutoff_hz);

}  // namespace moreau::mocap
