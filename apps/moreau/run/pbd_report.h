// What `moreau run` writes for the paper's cases: summary.json, trajectory.csv, trajectory.png.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "output.h"
#include "run/pbd_run.h"
#include "run/pbd_scenario.h"

namespace moreau::cli {

// sliding: "t,x0,…,x{d−1}", one row per frame; disks: "t,i,x,y", one row per disk and frame.
std::string PbdTrajectoryCsv(const PbdScenario& scenario, const PbdRunResult& result);

// The simulation summary's JSON with error, neighbour-list counters, the scenario's settings and
// the scenario file.
nlohmann::json PbdRunJson(const PbdScenario& scenario, const PbdRunResult& result,
                          const std::string& scenario_file);

// Writes SUMMARY as summary.json, trajectory.csv and, with `figures`, trajectory.png into OUT
// and commits it. Returns the brief report `moreau run` prints.
std::string ReportPbdRun(const PbdScenario& scenario, const PbdRunResult& result,
                         const nlohmann::json& summary, OutputDir& out, bool figures);

}  // namespace moreau::cli
