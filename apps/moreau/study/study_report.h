// What `moreau study` writes: study.csv, summary.json (observed orders, errors at equal work),
// convergence.png, and the table it prints.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "study/study_run.h"

namespace moreau::cli {

// "method,h,error,constraint_evaluations,total_seconds", one row per run.
std::string StudyCsv(const PbdStudyResult& result);

// Per method: observed order over the fit_points smallest h and over all h, the fitted h range
// and the runs; errors of every method at a few equal work budgets; the settings.
nlohmann::json StudyJson(const PbdScenario& scenario, const PbdStudyPlan& plan,
                         const PbdStudyResult& result, const std::string& scenario_file);

// Writes DIR, prints the table and the orders. Returns 0, or 128 + signal for a study stopped on
// request (its finished runs published, marked interrupted).
int ReportPbdStudy(const PbdScenario& scenario, const PbdStudyPlan& plan,
                   const PbdStudyResult& result, const std::string& scenario_file,
                   const std::string& out_dir);

}  // namespace moreau::cli
