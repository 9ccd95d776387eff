// One run of a sweep, in process: the base scenario with the run's overrides, read by the
// command's own scenario reader, run by its library entry point, and reduced to a table row.
#pragma once

#include <cstdint>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "sweep/sweep_scenario.h"

namespace moreau::cli {

// The summary.json the command would write for the run with these overrides, plus, for a
// particle run, "msd" (mean squared displacement from the initial to the final positions) and,
// with a room, "evacuation_time" (when the last person went out; null when some are still in).
// Writes run_dir (the command's summary.json and, for particles, the trajectory the scenario
// asks for) when it is not empty. Throws InputError or NumericalError like the command.
nlohmann::json RunSweepPoint(const SweepScenario& sweep, const std::vector<std::string>& overrides,
                             const std::filesystem::path& run_dir);

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
