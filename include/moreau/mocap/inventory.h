// What a recording holds, for `moreau inspect`: markers, frames, rate, units, the file's format
// and the table of gaps.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/mocap/recording.h"

namespace moreau::mocap {

// One gap in the units of the table: frames are 0-based indices into the recording (the file's
// frame number is first_frame + index), seconds = frames / rate.
struct GapRow {
  std::string marker;
  std::int64_t first_frame = 0;
  std::int64_t last_frame = 0;
  std::int64_t length_frames = 0;
  double length_seconds = 0.0;
};

struct RecordingInventory {
  int markers = 0;
  std::int64_t frames = 0;
  std::int64_t first_frame = 1;   // the file's number of frame 0
  double rate = 0.0;              // frames per second
  double duration_seconds = 0.0;  // frames / rate
  std::string units;
  SourceFormat format;
  std::vector<std::string> labels;
  std::vector<std::int64_t> observed_samples;  // per marker
  std::vector<GapRow> gaps;                    // by marker, then first frame
  std::vector<std::string> warnings;           // from reading the file

  // {"markers", "frames", "first_frame", "rate", "duration_seconds", "units", "format":
  //  {"container", "processor", "storage", "scale", "analog_channels",
  //   "analog_samples_per_frame"}, "labels", "observed_samples", "missing_samples",
  //  "gaps": [{"marker", "first_frame", "last_frame", "length_frames", "length_seconds"}],
  //  "warnings"}
  nlohmann::json ToJson() const;
};

// The inventory of `recording`, with the warnings its reader returned.
RecordingInventory TakeInventory(const Recording& recording,
                                 std::vector<std::string> warnings = {});

}  // namespace moreau::mocap
