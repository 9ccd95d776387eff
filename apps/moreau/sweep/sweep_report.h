// What `moreau sweep` writes once every run is in the journal: results.csv and results.h5 (one
// row per run, in grid order, whatever the number of ranks), summary.json, and the lines printed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "moreau/sweep/results_table.h"
#include "output.h"
#include "sweep/sweep_scenario.h"

namespace moreau::cli {

// How the sweep went (this invocation).
struct SweepCounts {
  std::int64_t runs = 0;     // in the grid
  std::int64_t skipped = 0;  // found in the journal, not run again
  int ranks = 1;
  int jobs = 1;                // threads per rank
  double run_seconds = 0.0;    // the runs of this invocation, summed over ranks and threads
  double total_seconds = 0.0;  // wall clock of this invocation
};

// Columns: run (grid position), hash, each axis key, the seed key (with seeds), status, each
// collected quantity, message. Throws InputError when a run of the grid is not in `journal`,
// unless `partial` (a sweep stopped on request): then such a run is a row with status
// "not_run" and empty cells.
sweep::ResultsTable SweepTable(const SweepScenario& sweep,
                               const std::map<std::string, nlohmann::json>& journal,
                               bool partial = false);

// Stages results.csv, results.h5 and summary.json in OUT (the sweep's folder, Publish::kMerge),
// publishes them and prints the brief report. Returns the exit code: 0 when every run of the
// table succeeded; 128 + signal when a run is "interrupted" or "not_run" (summary.json:
// termination "interrupted", ok false); else 3 (after one line on stderr counting the failed
// runs; they are rows of the table with their status and message).
int ReportSweep(const SweepScenario& sweep, const sweep::ResultsTable& table,
                const SweepCounts& counts, const std::string& sweep_file, OutputDir& out);

}  // namespace moreau::cli
