// What `moreau control` writes: summary.json, trajectory.csv, controls.csv and the figures for a
// run; convergence.csv (with the Theorem 5.1 bounds when the scenario gives the constants) and
// the finest trajectory for a study; and the lines it prints.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "control/control_run.h"
#include "control/control_scenario.h"
#include "moreau/control/pontryagin.h"
#include "moreau/control/value_error_bounds.h"

namespace moreau::cli {

// "t, node{j}_x{i} (every node), node{j}_v{i} (free nodes), ref{j}_x{i}, ref{j}_w (free nodes)".
std::string TrajectoryCsv(const control::PontryaginDiscretization& disc, const Eigen::MatrixXd& z);
// "t, spring{s}_{a}_{b}": the effective rest lengths on every interval.
std::string ControlsCsv(const control::PontryaginDiscretization& disc,
                        const Eigen::MatrixXd& controls);
// One row per N: value, differences, residual, Newton iterations, seconds, and the bounds.
std::string ConvergenceCsv(const control::RefinementStudySummary& study, double horizon,
                           const std::optional<control::ValueErrorConstants>& theorem);

// summary.json of a run: the continuation summary, value, residual, tracking RMS, steps, dt,
// δ, the settings and the scenario file.
nlohmann::json ControlRunJson(const ControlScenario& scenario, const ControlRunResult& result,
                              const std::string& scenario_file);

// Write DIR and print; return the exit code (0, or 3 when the solve or a level failed).
int ReportControlRun(const ControlScenario& scenario, const ControlRunResult& result,
                     const std::string& scenario_file, const std::string& out_dir);
int ReportControlStudy(const ControlScenario& scenario,
                       const control::RefinementStudySummary& study,
                       const std::string& scenario_file, const std::string& out_dir);

}  // namespace moreau::cli
