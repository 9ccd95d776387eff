// The complete part of a recording: the frames and markers on which every marker sample is
// observed, so that a recording with holes can still serve as ground truth (evaluate.h).
//
// Among frame ranges of at least `min_frames` frames whose ends lie on a grid of
// max(1, ⌈F / 100⌉) frames (and the last frame), the part is the range with the most marker
// samples (markers complete on it × its frames), and the markers complete on it; ties go to the
// earlier, then the shorter range. Points that are not markers (recording.h) are left out.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/mocap/recording.h"

namespace moreau::mocap {

struct CompletePart {
  std::int64_t first = 0;    // first frame of the part (0-based, in the input)
  std::int64_t frames = 0;   // frames in the part
  std::vector<int> markers;  // the input's markers observed at every frame of the part, in order

  // {"first_frame", "frames", "markers": kept labels, "dropped": the other markers' labels}.
  nlohmann::json ToJson(const Recording& in) const;
};

// The part above; markers is empty when no range of min_frames (≥ 1) frames has a complete
// marker.
CompletePart FindCompletePart(const Recording& in, std::int64_t min_frames);

// The part as a recording of its own: those markers (complete on the part, as FindCompletePart's
// are) over those frames (labels, rate, units,
// descriptions and format kept; first_frame advanced by part.first).
Recording ExtractPart(const Recording& in, const CompletePart& part);

}  // namespace moreau::mocap
