// One run of a sweep, in process: the base scenario with the run's overrides, read by the
// command's own scenario reader, run by its library entry point, and reduced to a table row.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/sweep/dispatch.h"
#include "scenario.h"
#include "sweep/sweep_scenario.h"

namespace moreau::cli {

// One run of the sweep, read and checked (and for command = "run" set up on its initial state,
// through the run command's own dispatch, run/dispatch.h); called with the run folder (empty:
// none), it runs and returns the summary.json the command writes for the run, writing the run
// folder (the command's summary.json and data files, no figures) when one is given.
using SweepPointRun = std::function<nlohmann::json(const std::filesystem::path& run_dir)>;

// The run with these overrides of the base scenario, prepared. Throws InputError exactly as
// the command would for the same scenario and --set values, before anything runs. With
// `check_only` every key and value is read and checked but nothing is set up (the returned run
// must not be called).
SweepPointRun PrepareSweepPoint(const SweepScenario& sweep,
                                const std::vector<std::string>& overrides, bool check_only = false);

// Every run of the grid checked before any runs: the base scenario with the [set] entries, the
// run's axis values and seed, read and checked as `moreau run --set` would; the first run is
// also set up on its initial state. Throws InputError "SWEEP: KEY: REASON" naming the sweep
// file, the key to blame (axes.KEY, set.KEY, seeds, or scenario when no sweep key is named) and
// the run ("the first run (…)" or "run I (…)" with its settings).
void CheckRuns(const SweepScenario& sweep, const Scenario& file);

// BODY on every rank of MPI (or in this one process). Under MPI an exception leaving BODY is
// reported before every rank is ended: its one line on stderr ("moreau: error: …", or the
// interrupted line of rank 0 after a stop request), then MPI_Abort with the tool's exit code
// (2 for bad input, 3 for a numerical failure, 128 + signal, else 1); the ranks other than 0
// print no "interrupted" line. Without MPI the exception goes on to main().
int RunOnRanks(const sweep::MpiSession& mpi, const std::function<int()>& body);

// Runs CHECKS (the input checks, before MPI starts). Every rank runs them and fails alike;
// under an MPI launcher only rank 0 lets their InputError go on to main() (one line, exit 2),
// the other ranks exit 2 without a line.
void CheckBeforeMpi(const std::function<void()>& checks);

// The journal entry of run `index`: {"hash", "index", "seconds", "row": {"status", "message",
// and each collected quantity}}. Never throws: a run that fails is a row whose status is the
// termination ("non_finite", …) or "input_error", "numerical_error", "error", with its message;
// a run stopped on request (signals.h) has status "interrupted" (RowInterrupted).
nlohmann::json SweepEntry(const SweepScenario& sweep, std::int64_t index,
                          const std::filesystem::path& out_dir);

// True when a row's status is a success ("completed", "converged").
bool RowSucceeded(const nlohmann::json& status);
// True when a row's status is "interrupted": the run did not finish (never journaled).
bool RowInterrupted(const nlohmann::json& status);

// The row's value of a dotted summary key ("stats.max_overlap"); null when absent.
nlohmann::json SummaryValue(const nlohmann::json& summary, const std::string& key);

}  // namespace moreau::cli
