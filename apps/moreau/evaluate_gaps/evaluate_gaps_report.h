// What `moreau evaluate-gaps` writes: evaluation.csv (one row per method, trial and hidden
// marker), summary.json (per method and gap length: mean, median and 90th percentile of the
// per-gap mean error, and the mean and 90th percentile of every other measure; the settings) and
// errors.png (position and acceleration errors against gap length); and the tables it prints
// (method × gap length).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "evaluate_gaps/evaluate_gaps_scenario.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/recording.h"

namespace moreau::cli {

// Header method,gap_frames,trial,marker,first_frame,mean_error,max_error,gap_seconds,status,
// p90_error,velocity_error,acceleration_error,velocity_jump_start,velocity_jump_end,
// distance_deviation,distance_z (EvaluationRow); marker is the label, lengths in the
// recording's units, times in seconds; a measure is empty when the gap was not filled or the
// measure does not exist there.
std::string EvaluationCsv(const mocap::EvaluationSummary& summary,
                          const mocap::Recording& recording);

// The summary's JSON without the per-trial rows (they are in evaluation.csv), with the input
// file, the recording's size and rate, and the settings keyed as in a scenario file.
nlohmann::json EvaluationSummaryJson(const EvaluateGapsSettings& settings,
                                     const mocap::EvaluationSummary& summary,
                                     const mocap::Recording& recording, const std::string& input);

// "method × gap length: mean / p90" in the recording's units.
std::string EvaluationTable(const mocap::EvaluationSummary& summary);

// "method × gap length": the means of the filtered acceleration error and of the velocity jump.
std::string DynamicsTable(const mocap::EvaluationSummary& summary);

// Writes DIR (staged, committed only once everything is written), prints the table and returns
// the exit code: 0, or 128 + signal when a stop request cut the trials short (the trials done
// are published, marked interrupted).
int ReportEvaluateGaps(const EvaluateGapsSettings& settings,
                       const mocap::EvaluationSummary& summary, const mocap::Recording& recording,
                       const std::string& input, const std::string& out_dir);

}  // namespace moreau::cli
