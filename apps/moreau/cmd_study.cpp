// `moreau study SCENARIO.toml --methods pbd,pngs,pgs,penalty[:gamma] --h 0.1,0.05,... [--out DIR]`:
// error against the exact (sliding) or reference (disks) solution for every method and step size,
// the observed orders, and the convergence and precision–work figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "moreau/common/error.h"
#include "output.h"
#include "pbd_scenario.h"
#include "progress.h"

namespace moreau::cli {
namespace {

struct StudyArgs {
  std::string scenario;
  std::vector<std::string> overrides;
  std::string out;
  std::vector<std::string> methods;
  std::vector<double> hs;
  int fit_points = 4;
};

nlohmann::json JsonNumber(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

int Study(const StudyArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  const PbdScenario pbd_scenario = ReadPbdScenario(scenario);
  scenario.CheckAllKeysUsed();

  std::vector<pbd::MethodSpec> methods;
  for (const std::string& m : args.methods) {
    try {
      methods.push_back(pbd::ParseMethodSpec(m));
    } catch (const InputError& e) {
      throw InputError(fmt::format("--methods: {}", e.what()));
    }
  }
  if (methods.empty()) throw InputError("--methods: at least one method is needed");
  std::vector<double> hs = args.hs;
  if (hs.empty()) throw InputError("--h: at least one step size is needed");
  for (double h : hs) {
    if (!(h > 0.0)) throw InputError(fmt::format("--h: step sizes must be > 0 (got {})", h));
    try {
      (void)StepCount(pbd_scenario.T(), h);
    } catch (const InputError& e) {
      throw InputError(fmt::format("--h: {}", e.what()));
    }
  }
  std::sort(hs.begin(), hs.end(), std::greater<>());
  if (args.fit_points < 2) throw InputError("--fit-points: must be ≥ 2");

  OutputDir out(args.out.empty()
                    ? (std::filesystem::path("out") /
                       (std::filesystem::path(args.scenario).stem().string() + "_study"))
                          .string()
                    : args.out);
  pbd::StudyProblem problem = pbd_scenario.MakeProblem();
  if (!problem.solution) {
    const double sample_dt = hs.back();
    try {
      (void)StepCount(sample_dt, pbd_scenario.reference.h);
    } catch (const InputError&) {
      scenario.Fail("reference.h", fmt::format("the smallest study step {} must be a whole "
                                               "multiple of it ({})", sample_dt,
                                               pbd_scenario.reference.h));
    }
    std::fprintf(stderr, "moreau: computing the reference solution (%s, h = %g, reltol = %g)\n",
                 std::string(pbd::MethodName(pbd_scenario.reference.method)).c_str(),
                 pbd_scenario.reference.h, pbd_scenario.reference.reltol);
    auto reference = std::make_shared<pbd::SampledTrajectory>(
        pbd::ComputeReference(problem, pbd_scenario.reference, sample_dt));
    problem.solution = [reference](double t) { return reference->At(t); };
  }

  ProgressBar progress("study", static_cast<std::int64_t>(methods.size() * hs.size()));
  const std::vector<pbd::StudyRow> rows =
      pbd::RunStudy(problem, methods, hs, pbd_scenario.solver,
                    [&](int done, int) { progress.Update(done); });
  progress.Finish();

  std::string csv = "method,h,error,constraint_evaluations,wall_seconds\n";
  for (const pbd::StudyRow& r : rows) {
    csv += fmt::format("{},{:.17g},{:.17g},{},{:.6g}\n", r.label, r.h, r.error,
                       r.constraint_evaluations, r.wall_seconds);
  }

  nlohmann::json j;
  j["scenario_file"] = args.scenario;
  j["settings"] = pbd_scenario.ToJson();
  j["fit_points"] = args.fit_points;
  std::printf("%-14s %12s %14s %16s %10s\n", "method", "h", "error", "evaluations", "seconds");
  for (const pbd::MethodSpec& m : methods) {
    std::vector<double> h_all, e_all;
    nlohmann::json runs = nlohmann::json::array();
    for (const pbd::StudyRow& r : rows) {
      if (r.label != m.label) continue;
      h_all.push_back(r.h);
      e_all.push_back(r.error);
      runs.push_back({{"h", r.h},
                      {"error", JsonNumber(r.error)},
                      {"constraint_evaluations", r.constraint_evaluations},
                      {"sweeps", r.sweeps},
                      {"max_violation", JsonNumber(r.max_violation)},
                      {"wall_seconds", r.wall_seconds},
                      {"ok", r.ok}});
      std::printf("%-14s %12.6g %14.6e %16lld %10.4f\n", r.label.c_str(), r.h, r.error,
                  static_cast<long long>(r.constraint_evaluations), r.wall_seconds);
    }
    // hs is sorted descending: the asymptotic range is the tail.
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(args.fit_points), h_all.size());
    const std::vector<double> h_fit(h_all.end() - static_cast<std::ptrdiff_t>(k), h_all.end());
    const std::vector<double> e_fit(e_all.end() - static_cast<std::ptrdiff_t>(k), e_all.end());
    j["methods"][m.label] = {{"observed_order", JsonNumber(pbd::ObservedOrder(h_fit, e_fit))},
                             {"observed_order_all_h", JsonNumber(pbd::ObservedOrder(h_all, e_all))},
                             {"fit_h_range", {h_fit.back(), h_fit.front()}},
                             {"runs", runs}};
  }
  // Errors at equal work: a few budgets inside the range every method covers.
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
  for (const pbd::MethodSpec& m : methods) {
    double mlo = std::numeric_limits<double>::infinity(), mhi = 0.0;
    for (const pbd::StudyRow& r : rows) {
      if (r.label != m.label || !r.ok) continue;
      mlo = std::min(mlo, static_cast<double>(r.constraint_evaluations));
      mhi = std::max(mhi, static_cast<double>(r.constraint_evaluations));
    }
    lo = std::max(lo, mlo);
    hi = std::min(hi, mhi);
  }
  nlohmann::json budgets = nlohmann::json::array();
  if (lo > 0.0 && hi > lo) {
    for (int i = 0; i <= 4; ++i) {
      const double b = lo * std::pow(hi / lo, i / 4.0);
      nlohmann::json entry{{"constraint_evaluations", b}};
      for (const pbd::MethodSpec& m : methods) {
        entry["error"][m.label] = JsonNumber(pbd::ErrorAtBudget(rows, m.label, b));
      }
      budgets.push_back(entry);
    }
  }
  j["equal_work"] = budgets;
  std::printf("\nobserved order (least squares over the %d smallest h):\n", args.fit_points);
  for (const pbd::MethodSpec& m : methods) {
    const auto& o = j["methods"][m.label]["observed_order"];
    std::printf("  %-14s %s\n", m.label.c_str(),
                o.is_null() ? "n/a" : fmt::format("{:.3f}", o.get<double>()).c_str());
  }

  out.WriteText("study.csv", csv);
  out.WriteText("summary.json", j.dump(2) + "\n");
  RunPlotScript("plot_study.py", {out.StagedPath("study.csv").string(),
                                  out.Stage("convergence.png").string(),
                                  fmt::format("{} case", pbd_scenario.kind)});
  out.Commit();
  std::printf("wrote %s/study.csv, summary.json, convergence.png\n", out.dir().c_str());
  return 0;
}

}  // namespace

void AddStudyCommand(CLI::App& app) {
  auto args = std::make_shared<StudyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Convergence and precision-work study over methods and step sizes");
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--methods", args->methods, "pbd,pngs,pgs,penalty[:gamma]")
      ->delimiter(',')
      ->required();
  cmd->add_option("--h", args->hs, "Step sizes, e.g. 0.1,0.05,0.025")->delimiter(',')->required();
  cmd->add_option("--set", args->overrides, "Override a scenario value: key=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder (default out/<scenario name>_study)");
  cmd->add_option("--fit-points", args->fit_points,
                  "How many of the smallest step sizes the observed order is fitted over")
      ->capture_default_str();
  cmd->callback([args] {
    const int code = Study(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace moreau::cli
