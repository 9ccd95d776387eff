// What a recording holds, for `moreau inspect`: markers, model outputs, frames, rate, units, the
// file's format and the table of the markers' gaps.
#pragma once

#include <array>
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

// A point that is not a marker (recording.h): a model output, with the units its file states.
struct ModelOutputRow {
  std::string label;
  PointType type = PointType::kAngle;
  std::string units;
  std::int64_t observed_samples = 0;
};

struct RecordingInventory {
  int markers = 0;                                  // points of type marker
  std::array<int, kPointTypeCount> point_counts{};  // points per PointType
  std::int64_t frames = 0;
  std::int64_t first_frame = 1;   // the file's number of frame 0
  double rate = 0.0;              // frames per second
  double duration_seconds = 0.0;  // frames / rate
  std::string units;
  SourceFormat format;
  std::vector<std::string> labels;             // of the markers
  std::vector<std::int64_t> observed_samples;  // per marker
  std::vector<GapRow> gaps;                    // by marker, then first frame
  std::vector<ModelOutputRow> model_outputs;   // in the file's order
  std::vector<std::string> warnings;           // from reading the file

  // {"markers", "frames", "first_frame", "rate", "duration_seconds", "units", "format":
  //  {"container", "processor", "storage", "scale", "analog_channels",
  //   "analog_samples_per_frame"}, "labels", "observed_samples", "missing_samples",
  //  "gaps": [{"marker", "first_frame", "last_frame", "length_frames", "length_seconds"}],
  //  "point_types": {"marker": n, "angle": n, "force": n, "moment": n, "power": n, "scalar": n,
  //  "reaction": n}, "model_outputs": [{"label", "type", "units", "observed_samples"}],
  //  "warnings"}; labels, observed_samples and missing_samples are the markers'.
  nlohmann::json ToJson() const;
};

// The inventory of `recording`, with the warnings its reader returned.
RecordingInventory TakeInventory(const Recording& recording,
                                 std::vector<std::string> warnings = {});

}  // namespace moreau::mocap
