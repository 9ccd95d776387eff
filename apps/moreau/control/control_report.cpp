#include "control/control_report.h"

#include <cmath>
#include <cstdio>
#include <iterator>

#include <fmt/format.h>

#include "moreau/common/summary_json.h"
#include "output.h"

namespace moreau::cli {
namespace {

using control::PontryaginDiscretization;

void TrajectoryHeader(const control::SpringNetwork& net, fmt::memory_buffer& b) {
  auto out = std::back_inserter(b);
  const int d = net.dimension();
  fmt::format_to(out, "t");
  for (int j = 0; j < net.num_nodes(); ++j) {
    for (int i = 0; i < d; ++i) fmt::format_to(out, ",node{}_x{}", j, i);
  }
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) continue;
    for (int i = 0; i < d; ++i) fmt::format_to(out, ",node{}_v{}", j, i);
  }
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) continue;
    for (int i = 0; i < d; ++i) fmt::format_to(out, ",ref{}_x{}", j, i);
    fmt::format_to(out, ",ref{}_w", j);
  }
  fmt::format_to(out, "\n");
}

}  // namespace

std::string TrajectoryCsv(const PontryaginDiscretization& disc, const Eigen::MatrixXd& z) {
  const control::SpringNetwork& net = disc.problem().network();
  const int d = net.dimension();
  fmt::memory_buffer b;
  TrajectoryHeader(net, b);
  auto out = std::back_inserter(b);
  for (int n = 0; n <= disc.steps(); ++n) {
    const control::Instant& in = disc.instant(n);
    fmt::format_to(out, "{:.17g}", in.t);
    for (int j = 0; j < net.num_nodes(); ++j) {
      const int k = net.free_index(j);
      for (int i = 0; i < d; ++i) {
        fmt::format_to(out, ",{:.17g}", k < 0 ? in.fixed_position[d * j + i] : z(2 * d * k + i, n));
      }
    }
    for (int k = 0; k < net.num_free(); ++k) {
      for (int i = 0; i < d; ++i) fmt::format_to(out, ",{:.17g}", z(2 * d * k + d + i, n));
    }
    for (int k = 0; k < net.num_free(); ++k) {
      for (int i = 0; i < d; ++i) fmt::format_to(out, ",{:.17g}", in.ref_position[d * k + i]);
      fmt::format_to(out, ",{:.17g}", in.ref_weight[k]);
    }
    fmt::format_to(out, "\n");
  }
  return fmt::to_string(b);
}

std::string ControlsCsv(const PontryaginDiscretization& disc, const Eigen::MatrixXd& controls) {
  const control::SpringNetwork& net = disc.problem().network();
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "t");
  for (int s = 0; s < net.num_springs(); ++s) {
    fmt::format_to(out, ",spring{}_{}_{}", s, net.spring(s).a, net.spring(s).b);
  }
  fmt::format_to(out, "\n");
  for (int n = 0; n < disc.steps(); ++n) {
    fmt::format_to(out, "{:.17g}", disc.instant(n).t);
    for (int s = 0; s < net.num_springs(); ++s) fmt::format_to(out, ",{:.17g}", controls(s, n));
    fmt::format_to(out, "\n");
  }
  return fmt::to_string(b);
}

std::string ConvergenceCsv(const control::RefinementStudySummary& study, double horizon,
                           const std::optional<control::ValueErrorConstants>& theorem) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out,
                 "steps,dt,ok,value,value_minus_finest,residual_norm,newton_iterations,"
                 "newton_total,total_seconds,diff_previous,diff_finest,tracking_rms,bound_lower,"
                 "bound_upper\n");
  const double u_finest = study.levels.back().value;
  for (const control::RefinementLevel& l : study.levels) {
    const double dt = horizon / l.steps;
    std::string bounds = ",,";
    if (theorem) {
      const control::ValueErrorBounds vb = control::Theorem51Bounds(*theorem, horizon, dt);
      bounds = fmt::format(",{:.17g},{:.17g}", vb.lower, vb.upper);
    }
    // A level that did not converge has no value (empty cells), only its residual.
    const auto number = [&l](double v) { return l.ok() ? fmt::format("{:.17g}", v) : ""; };
    fmt::format_to(out, "{},{:.17g},{},{},{},{:.6e},{},{},{:.6f},{},{},{:.6e}{}\n", l.steps, dt,
                   l.ok() ? 1 : 0, number(l.value),
                   study.levels.back().ok() ? number(u_finest - l.value) : "", l.residual,
                   l.newton_iterations, l.newton_total, l.total_seconds,
                   std::isfinite(l.diff_previous) ? fmt::format("{:.6e}", l.diff_previous) : "",
                   fmt::format("{:.6e}", l.diff_finest), l.tracking_rms, bounds);
  }
  return fmt::to_string(b);
}

nlohmann::json ControlRunJson(const ControlScenario& scenario, const ControlRunResult& r,
                              const std::string& scenario_file) {
  nlohmann::json j = r.continuation.ToJson();
  j["total_seconds"] = r.total_seconds;  // the whole command: solve and evaluation
  // A failed solve has no value and no tracking error: null, and "message" says why; the
  // residual of the last iterate shows how far it is from a solution.
  const bool solved = r.continuation.ok();
  j["value"] = solved ? FiniteOrNull(r.value) : nlohmann::json();
  j["residual_norm"] = FiniteOrNull(r.residual_norm);
  j["tracking_rms"] = solved ? FiniteOrNull(r.tracking_rms) : nlohmann::json();
  j["steps"] = scenario.steps;
  j["dt"] = r.dt;
  j["delta"] = r.delta;
  j["settings"] = EchoControlScenario(scenario);
  j["scenario_file"] = scenario_file;
  return j;
}

int ReportControlRun(const ControlScenario& scenario, const ControlRunResult& r,
                     const std::string& scenario_file, const std::string& out_dir) {
  const control::ContinuationSummary& cs = r.continuation;
  const nlohmann::json j = ControlRunJson(scenario, r, scenario_file);

  const PontryaginDiscretization disc(MakeProblemFamily(scenario)(1.0), scenario.steps);
  OutputDir out(out_dir);
  out.WriteText("summary.json", JsonText(j) + "\n");
  out.WriteText("trajectory.csv", TrajectoryCsv(disc, r.z));
  out.WriteText("controls.csv", ControlsCsv(disc, r.controls));
  RunPlotScript("plot_control.py", {"run", out.Stage("trajectory.png").string(),
                                    out.StagedPath("trajectory.csv").string(),
                                    out.StagedPath("controls.csv").string()});
  out.Commit();
  std::printf("%s\n", cs.BriefReport().c_str());
  if (cs.ok()) {
    std::printf("value %.12g, residual %.3e, tracking RMS %.3e, %d steps, %.2f s\n", r.value,
                r.residual_norm, r.tracking_rms, scenario.steps, r.total_seconds);
  } else {
    std::printf("no solution: residual %.3e, %d steps, %.2f s\n", r.residual_norm, scenario.steps,
                r.total_seconds);
  }
  std::printf("wrote %s/summary.json, trajectory.csv, controls.csv, trajectory.png\n",
              out.dir().c_str());
  if (!cs.ok()) {
    std::fprintf(stderr, "moreau: control did not converge: %s\n", cs.message.c_str());
    return 3;
  }
  return 0;
}

int ReportControlStudy(const ControlScenario& scenario,
                       const control::RefinementStudySummary& study,
                       const std::string& scenario_file, const std::string& out_dir) {
  const control::RefinementLevel& finest = study.levels.back();
  nlohmann::json j = study.ToJson();
  j["value"] = finest.ok() ? FiniteOrNull(finest.value) : nlohmann::json();
  j["newton_iterations"] = finest.newton_iterations;
  j["residual_norm"] = FiniteOrNull(finest.residual);
  j["settings"] = EchoControlScenario(scenario);
  j["scenario_file"] = scenario_file;

  const control::TrackingProblem target = MakeProblemFamily(scenario)(1.0);
  const PontryaginDiscretization disc(target, finest.steps);
  OutputDir out(out_dir);
  out.WriteText("summary.json", JsonText(j) + "\n");
  out.WriteText("convergence.csv", ConvergenceCsv(study, target.horizon(), scenario.theorem));
  out.WriteText("trajectory.csv", TrajectoryCsv(disc, finest.z));  // the finest, as for a run
  out.WriteText("controls.csv", ControlsCsv(disc, finest.controls));
  RunPlotScript("plot_control.py", {"study", out.Stage("value_vs_steps.png").string(),
                                    out.Stage("difference_vs_steps.png").string(),
                                    out.StagedPath("convergence.csv").string()});
  out.Commit();
  std::printf("%-8s %-10s %-22s %-12s %-12s %-12s %-10s\n", "N", "converged", "value", "residual",
              "diff_prev", "diff_finest", "rms");
  for (const control::RefinementLevel& l : study.levels) {
    std::printf("%-8d %-10s %-22.15g %-12.3e %-12.3e %-12.3e %-10.3e\n", l.steps,
                l.ok() ? "yes" : "no", l.value, l.residual, l.diff_previous, l.diff_finest,
                l.tracking_rms);
  }
  std::printf(
      "wrote %s/summary.json, convergence.csv, value_vs_steps.png, "
      "difference_vs_steps.png\n",
      out.dir().c_str());
  if (!study.ok()) {
    std::fprintf(stderr, "moreau: some levels of the study did not converge\n");
    return 3;
  }
  return 0;
}

}  // namespace moreau::cli
