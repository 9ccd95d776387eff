#include "study/study_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"
#include "output.h"
#include "signals.h"

namespace moreau::cli {
namespace {

nlohmann::json MethodJson(const std::vector<pbd::StudyRow>& rows, const std::string& label,
                          int fit_points) {
  std::vector<double> h_all, e_all;
  nlohmann::json runs = nlohmann::json::array();
  for (const pbd::StudyRow& r : rows) {
    if (r.label != label) continue;
    h_all.push_back(r.h);
    e_all.push_back(r.error);
    runs.push_back(r.ToJson());
  }
  if (h_all.empty()) {  // a study stopped before any run of this method finished
    return {{"observed_order", nullptr},
            {"observed_order_all_h", nullptr},
            {"fit_h_range", nullptr},
            {"runs", runs}};
  }
  // The rows run from large to small h: the asymptotic range is the tail.
  const auto k = static_cast<std::ptrdiff_t>(
      std::min<std::size_t>(static_cast<std::size_t>(fit_points), h_all.size()));
  const std::vector<double> h_fit(h_all.end() - k, h_all.end());
  const std::vector<double> e_fit(e_all.end() - k, e_all.end());
  return {{"observed_order", FiniteOrNull(pbd::ObservedOrder(h_fit, e_fit))},
          {"observed_order_all_h", FiniteOrNull(pbd::ObservedOrder(h_all, e_all))},
          {"fit_h_range", {h_fit.back(), h_fit.front()}},
          {"runs", runs}};
}

// Errors at equal work: a few budgets inside the range of evaluations every method covers.
nlohmann::json EqualWorkJson(const std::vector<pbd::StudyRow>& rows,
                             const std::vector<pbd::MethodSpec>& methods) {
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
  for (const pbd::MethodSpec& m : methods) {
    double mlo = std::numeric_limits<double>::infinity(), mhi = 0.0;
    for (const pbd::StudyRow& r : rows) {
      if (r.label != m.label || !r.ok()) continue;
      mlo = std::min(mlo, static_cast<double>(r.constraint_evaluations));
      mhi = std::max(mhi, static_cast<double>(r.constraint_evaluations));
    }
    lo = std::max(lo, mlo);
    hi = std::min(hi, mhi);
  }
  nlohmann::json budgets = nlohmann::json::array();
  if (!(lo > 0.0 && hi > lo)) return budgets;
  for (int i = 0; i <= 4; ++i) {
    const double b = lo * std::pow(hi / lo, i / 4.0);
    nlohmann::json entry{{"constraint_evaluations", b}};
    for (const pbd::MethodSpec& m : methods) {
      entry["error"][m.label] = FiniteOrNull(pbd::ErrorAtBudget(rows, m.label, b));
    }
    budgets.push_back(entry);
  }
  return budgets;
}

void PrintStudy(const PbdStudyPlan& plan, const PbdStudyResult& result, const nlohmann::json& j) {
  std::printf("%-14s %12s %14s %16s %10s\n", "method", "h", "error", "evaluations", "seconds");
  for (const pbd::MethodSpec& m : plan.methods) {
    for (const pbd::StudyRow& r : result.rows) {
      if (r.label != m.label) continue;
      std::printf("%-14s %12.6g %14.6e %16lld %10.4f\n", r.label.c_str(), r.h, r.error,
                  static_cast<long long>(r.constraint_evaluations), r.total_seconds);
    }
  }
  std::printf("\nobserved order (least squares over the %d smallest h):\n", plan.fit_points);
  for (const pbd::MethodSpec& m : plan.methods) {
    const auto& o = j["methods"][m.label]["observed_order"];
    std::printf("  %-14s %s\n", m.label.c_str(),
                o.is_null() ? "n/a" : fmt::format("{:.3f}", o.get<double>()).c_str());
  }
}

}  // namespace

std::string StudyCsv(const PbdStudyResult& result) {
  std::string csv = "method,h,error,constraint_evaluations,total_seconds\n";
  for (const pbd::StudyRow& r : result.rows) {
    csv += fmt::format("{},{:.17g},{:.17g},{},{:.6g}\n", r.label, r.h, r.error,
                       r.constraint_evaluations, r.total_seconds);
  }
  return csv;
}

nlohmann::json StudyJson(const PbdScenario& scenario, const PbdStudyPlan& plan,
                         const PbdStudyResult& result, const std::string& scenario_file) {
  const auto failed = std::count_if(result.rows.begin(), result.rows.end(),
                                    [](const pbd::StudyRow& r) { return !r.ok(); });
  nlohmann::json j =
      SummaryJson(failed == 0 ? Termination::kCompleted : Termination::kNonFinite,
                  failed == 0 ? "" : fmt::format("{} runs failed", failed), result.total_seconds);
  if (result.interrupted) {
    j = SummaryJson(Termination::kInterrupted,
                    fmt::format("stopped on request: {} of {} runs finished{}", result.rows.size(),
                                result.runs, failed == 0 ? "" : fmt::format(", {} failed", failed)),
                    result.total_seconds);
  }
  j["scenario_file"] = scenario_file;
  j["settings"] = EchoPbdScenario(scenario);
  j["fit_points"] = plan.fit_points;
  for (const pbd::MethodSpec& m : plan.methods) {
    j["methods"][m.label] = MethodJson(result.rows, m.label, plan.fit_points);
  }
  j["equal_work"] = EqualWorkJson(result.rows, plan.methods);
  return j;
}

int ReportPbdStudy(const PbdScenario& scenario, const PbdStudyPlan& plan,
                   const PbdStudyResult& result, const std::string& scenario_file,
                   const std::string& out_dir) {
  const nlohmann::json j = StudyJson(scenario, plan, result, scenario_file);
  OutputDir out(out_dir);
  out.WriteText("study.csv", StudyCsv(result));
  out.WriteText("summary.json", JsonText(j) + "\n");
  RunPlotScript("plot_study.py",
                {out.StagedPath("study.csv").string(), out.Stage("convergence.png").string(),
                 fmt::format("{} case", scenario.kind)});
  out.Commit(WhenStopped::kPublish);  // a study stopped on request: the runs finished
  PrintStudy(plan, result, j);
  std::printf("wrote %s/study.csv, summary.json, convergence.png\n", out.dir().c_str());
  return result.interrupted ? ReportInterrupted(j["message"].get<std::string>()) : 0;
}

}  // namespace moreau::cli
