// One run of a sweep, in process: the base scenario with the run's overrides, read by the
// command's own scenario reader, run by its library entry point, and reduced to a table row.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario.h"
#include "sweep/sweep_scenario.h"

namespace moreau::cli {

// One run of the sweep, read and checked (and for command = "run" set up on its initial state,
// through the run command's own dispatch, run/dispatch.h); called with the run folder (empty:
// none), it runs and returns the summary.json the command writes for the run, writing the run
// folder (the command's summary.json and data files, no figures) when one is given.
using SweepPointRun = std::function<nlohmann::json(const std::filesystem::path& run_dir)>;

// The run with these overrides of the base scenario, prepared. Throws InputError exactly as
// the command would for the same scenario and --set values, before anything runs.
SweepPointRun PrepareSweepPoint(const SweepScenario& sweep,
                                const std::vector<std::string>& overrides);

// The first run of the grid prepared and dropped (every axis key, the seed key and the [set]
// entries applied to the base scenario and checked, as `moreau run --set` would). Throws
// InputError "SWEEP: KEY: REASON" naming the sweep file and the key to blame (axes.KEY,
// set.KEY, seeds, or scenario when no sweep key is named).
void CheckFirstRun(const SweepScenario& sweep, const Scenario& file);

// The journal entry of run `index`: {"hash", "index", "seconds", "row": {"status", "message",
// and each collected quantity}}. Never throws: a run that fails is a row whose status is the
// termination ("non_finite", …) or "input_error", "numerical_error", "error", with its message.
nlohmann::json SweepEntry(const SweepScenario& sweep, std::int64_t index,
                          const std::filesystem::path& out_dir);

// True when a row's status is a success ("completed", "converged").
bool RowSucceeded(const nlohmann::json& status);

// The row's value of a dotted summary key ("stats.max_overlap"); null when absent.
nlohmann::json SummaryValue(const nlohmann::json& summary, const std::string& key);

}  // namespace moreau::cli
