// What `moreau fill-gaps` writes: filled.c3d, filled.csv (every frame and marker, the input's
// units), report.json (the gaps counted by outcome; per gap: marker, label, first, last, method,
// status, outcome, prior_reason, message, seconds and, for deleted samples, the error; the
// settings) and gaps.png when the figure script succeeds; and the lines it prints ("wrote …"
// names only the files written).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fill_gaps/fill_gaps_run.h"
#include "fill_gaps/fill_gaps_scenario.h"

namespace moreau::cli {

struct FillGapsInputs {
  std::string recording;  // IN
  std::string gaps_file;  // GAPS.csv, or empty
};

// The fill summary's JSON with the recording's units, rate and size, the samples deleted, the
// error of each gap made of deleted samples, and the settings (keyed as in a scenario file).
nlohmann::json FillGapsReportJson(const FillGapsSettings& settings, const FillGapsResult& result,
                                  const FillGapsInputs& inputs);

// Writes DIR (staged, committed only once everything is written), prints the brief report (the
// summary's message, so the counts agree with report.json), one warning line per marker missing
// in every frame and one if the figure fails, and returns the exit code (0).
int ReportFillGaps(const FillGapsSettings& settings, const FillGapsResult& result,
                   const FillGapsInputs& inputs, const std::string& out_dir);

}  // namespace moreau::cli
