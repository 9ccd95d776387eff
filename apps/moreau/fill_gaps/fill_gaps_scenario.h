// The settings of `moreau fill-gaps` (one field table: fill.method, fill.max_gap_seconds, each
// method's block, read.*) and the list of samples to delete first (GAPS.csv).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "mocap_settings.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"
#include "moreau/mocap/recording_io.h"
#include "scenario.h"

namespace moreau::cli {

struct FillGapsSettings {
  mocap::ReadOptions read;
  mocap::GapFillOptions fill = DefaultFill();

  static mocap::GapFillOptions DefaultFill() {
    mocap::GapFillOptions options;
    options.method = kDefaultFillMethod;
    return options;
  }
};

FieldTable<FillGapsSettings> FillGapsFields();

// Reads and validates every key; throws InputError "SOURCE: KEY: REASON".
FillGapsSettings ReadFillGapsSettings(Scenario& scenario);

// The settings used, keyed as in a scenario file.
nlohmann::json EchoFillGapsSettings(const FillGapsSettings& settings);

// GAPS.csv: one line `marker,first_frame,last_frame` per run of samples to delete (an optional
// header line starting with "marker", blank lines and lines starting with '#' are skipped). The
// marker is a label of `recording`, or else a 0-based marker index; frames are 0-based and
// inclusive, 0 ≤ first ≤ last < frames. Throws InputError "FILE: line N: FIELD: reason", or
// "FILE: lines A and B: duplicate rows (…)" / "… overlapping rows (…)" when two rows of one
// marker share a frame.
std::vector<mocap::Gap> ReadGapList(const std::string& path, const mocap::Recording& recording);

}  // namespace moreau::cli
