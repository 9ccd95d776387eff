// The sweep file of `moreau sweep` (docs/sweeps.md): the command and base scenario every run
// starts from, fixed overrides [set], the axes [axes] (crossed or zipped), the seeds, and the
// quantities to collect from each run's summary.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "moreau/sweep/grid.h"
#include "scenario.h"

namespace moreau::cli {

struct SweepScenario {
  std::string command;    // "run", "control" or "fill-gaps"
  std::string scenario;   // base scenario file (fill-gaps: optional settings file), as a path
                          // from the working folder (written relative to the sweep file)
  std::string recording;  // fill-gaps: the recording (.c3d, .trc, .csv)
  std::vector<sweep::Setting> fixed;  // [set]: overrides of the base for every run
  sweep::Grid grid;                   // [axes], combine, seeds, seed_key
  std::vector<std::string> collect;   // dotted keys of the run's summary.json
  bool run_folders = false;           // DIR/runs/<hash>/ with the run's summary.json (and the
                                      // trajectory the base scenario asks for)
  std::string context;                // what RunHash fingerprints besides the settings

  // The overrides of run `index`: [set], then the run's settings, as "key=value".
  std::vector<std::string> Overrides(std::int64_t index) const;
};

// Reads and checks the sweep file (throws InputError "FILE: KEY: REASON"); reads the base
// scenario's bytes for the context, so a missing base is an error here, before any run.
SweepScenario ReadSweepScenario(Scenario& file);

// Every key of a sweep file (`moreau keys sweep`).
std::vector<KeyRow> SweepKeys();

// The settings used, keyed like the sweep file.
nlohmann::json EchoSweepScenario(const SweepScenario& sweep);

// A TOML literal ("1.2", "\"pbd\"", "[1, 2]") as a table cell: a number, a boolean, a string
// without quotes, or the literal itself for arrays.
nlohmann::json LiteralCell(const std::string& literal);

}  // namespace moreau::cli
