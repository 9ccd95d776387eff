// A mass–spring–damper network built from a recording: the model the optimal-control gap fill
// steers (include/moreau/mocap/ocp_fill.h).
//
// Nodes are markers (points of other types, recording.h, get no spring). For every pair of
// markers seen together in at least `min_common_frames` frames the distance d_ab(f) is measured
// over those frames: mean, spread (standard deviation), minimum and maximum. Each marker is joined
// to its `partners` most rigid partners (smallest spread; a pair is a spring once, whichever end
// chose it), so a marker usually has more springs than it chose. Rest-length bounds come from the
// observed range with a margin:
//   L− = max(0, d_min − m),  L+ = d_max + m,  m = bound_margin (d_max − d_min) + bound_floor
//   d_mean.
// Dynamics (units: the recording's length unit, seconds, unit
// mass per marker): every node has mass 1, every spring the natural period
// T_n = natural_period_seconds, i.e. κ = (2π / T_n)², and the damping ratio ζ, ξ = 2 ζ √κ.
// The network is written to reports by MarkerNetwork::ToJson.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/field_list.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

struct MarkerNetworkOptions {
  // Springs each marker chooses to its most rigid partners (>= 1; 3 are needed in 3D for a
  // hidden marker to stay determined). They are also the distances that judge a candidate fill
  // (ocp_fill.h): more of them, fewer wrong weights (docs/mocap.md).
  int partners = 10;
  int min_common_frames = 10;  // a pair seen together in fewer frames is never a spring (>= 2)
  double bound_margin = 0.1;   // m = bound_margin (d_max − d_min) + bound_floor d_mean (>= 0)
  double bound_floor = 0.01;   // relative floor of the margin (>= 0; keeps L− < L+)
  double natural_period_seconds = 0.065;  // T_n: κ = (2π / T_n)² (> 0)
  double damping_ratio = 1.0;             // ζ: ξ = 2 ζ √κ (>= 0; 1 = critical for one spring)
  // Explicit springs by marker label; when non-empty they replace the automatic choice (their
  // statistics and bounds are still measured from the recording).
  std::vector<std::pair<std::string, std::string>> springs;

  // Every field but `springs` (a list of label pairs, set from C++ or Python).
  static const FieldList<MarkerNetworkOptions>& Fields();
  // Throws InputError(key, reason) for a value out of range.
  void Validate() const;
  nlohmann::json ToJson() const;
};

// One spring between markers a < b, with the distance statistics it was chosen by (recording
// units) and its rest-length bounds.
struct MarkerSpring {
  int a = 0;
  int b = 0;
  std::int64_t common_frames = 0;  // frames where both markers are observed
  double mean = 0.0;               // mean distance
  double spread = 0.0;             // standard deviation of the distance
  double min = 0.0;                // smallest observed distance
  double max = 0.0;                // largest observed distance
  double rest_min = 0.0;           // L−
  double rest_max = 0.0;           // L+
};

struct MarkerNetwork {
  std::vector<MarkerSpring> springs;
  std::vector<std::vector<int>> springs_of;  // per marker: indices of its springs
  double length_scale = 1.0;  // median mean spring length (recording units), the OCP's unit
  double mass = 1.0;          // per node
  double stiffness = 0.0;     // κ in 1/s² (per unit mass)
  double damping = 0.0;       // ξ in 1/s (per unit mass)

  // The marker at the other end of spring s from marker m.
  int Partner(int s, int m) const;
  // {"springs": [{"a": label, "b": label, "common_frames", "mean", "spread", "min", "max",
  //  "rest_min", "rest_max"}...], "length_scale", "mass", "stiffness", "damping"}.
  nlohmann::json ToJson(const Recording& recording) const;
};

// Builds the network. Throws InputError when the options are invalid or an explicit spring names
// an unknown label, joins a marker to itself, or joins two markers never seen together in
// `min_common_frames` frames. A marker with no candidate partner simply gets no spring (the gap
// fill rejects gaps of such markers).
MarkerNetwork BuildMarkerNetwork(const Recording& recording, const MarkerNetworkOptions& options);

}  // namespace moreau::mocap
