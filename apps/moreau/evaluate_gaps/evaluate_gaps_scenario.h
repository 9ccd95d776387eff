// The settings of `moreau evaluate-gaps` in one field table: evaluation.methods,
// evaluation.gap_seconds, evaluation.trials, evaluation.seed, evaluation.threads,
// evaluation.filter_hz, evaluation.markers_per_gap, evaluation.placement,
// evaluation.distance_partners, fill.max_gap_seconds, each method's block (interpolation.*,
// rigid.*, pca.*) and read.*.
#pragma once

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/recording_io.h"
#include "scenario.h"

namespace moreau::cli {

struct EvaluateGapsSettings {
  mocap::ReadOptions read;
  mocap::EvaluationOptions evaluation;
};

FieldTable<EvaluateGapsSettings> EvaluateGapsFields();

// Reads and validates every key; throws InputError "SOURCE: KEY: REASON".
EvaluateGapsSettings ReadEvaluateGapsSettings(Scenario& scenario);

// The settings used, keyed as in a scenario file.
nlohmann::json EchoEvaluateGapsSettings(const EvaluateGapsSettings& settings);

}  // namespace moreau::cli
