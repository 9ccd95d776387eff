// `moreau run SCENARIO.toml [--set key=value ...] [--out DIR]`: one simulation.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "moreau/common/error.h"
#include "output.h"
#include "particles_run.h"
#include "pbd_scenario.h"
#include "progress.h"

namespace moreau::cli {
namespace {

struct RunArgs {
  std::string scenario;
  std::vector<std::string> overrides;
  std::string out;
  bool fix_overlaps = false;
};

std::string DefaultOut(const std::string& scenario, const std::string& suffix) {
  return (std::filesystem::path("out") / (std::filesystem::path(scenario).stem().string() + suffix))
      .string();
}

int Run(const RunArgs& args) {
  Scenario scenario = Scenario::Load(args.scenario, args.overrides);
  if (scenario.GetString("problem.kind", "") == "particles") {
    return RunParticleScenario(
        scenario, {args.out.empty() ? DefaultOut(args.scenario, "") : args.out, args.fix_overlaps});
  }
  const PbdScenario pbd_scenario = ReadPbdScenario(scenario);
  scenario.CheckAllKeysUsed();

  OutputDir out(args.out.empty() ? DefaultOut(args.scenario, "") : args.out);
  pbd::StudyProblem problem = pbd_scenario.MakeProblem();
  const pbd::StepperOptions& options = pbd_scenario.solver;
  const std::int64_t steps = StepCount(problem.T, options.h);

  if (pbd_scenario.disks && pbd_scenario.reference_for_run) {
    std::fprintf(stderr, "moreau: computing the reference solution (PNGS, h = %g)\n",
                 pbd_scenario.reference.h);
    auto reference = std::make_shared<pbd::SampledTrajectory>(
        pbd::ComputeReference(problem, pbd_scenario.reference, options.h));
    problem.solution = [reference](double t) { return reference->At(t); };
  }

  const bool particles = pbd_scenario.disks.has_value();
  const std::int64_t stride = pbd_scenario.output_stride > 0
                                  ? pbd_scenario.output_stride
                                  : std::max<std::int64_t>(1, steps / 1000);
  fmt::memory_buffer csv;
  if (particles) {
    fmt::format_to(std::back_inserter(csv), "t,i,x,y\n");
  } else {
    fmt::format_to(std::back_inserter(csv), "t");
    for (int i = 0; i < static_cast<int>(problem.x0.size()); ++i) {
      fmt::format_to(std::back_inserter(csv), ",x{}", i);
    }
    fmt::format_to(std::back_inserter(csv), "\n");
  }

  double error = 0.0;
  ProgressBar progress("run", steps);
  auto constraints = problem.constraints->MakeWorkspace();
  pbd::Vector final_state;
  const pbd::SimulationSummary summary = pbd::Simulate(
      *problem.drift, *constraints, options, problem.x0, problem.T,
      [&](std::int64_t k, double t, pbd::ConstVectorRef x) {
        if (problem.solution) error = std::max(error, (x - problem.solution(t)).norm());
        if (k % stride == 0 || k == steps) {
          if (particles) {
            for (int i = 0; i < static_cast<int>(x.size() / 2); ++i) {
              fmt::format_to(std::back_inserter(csv), "{:.17g},{},{:.17g},{:.17g}\n", t, i,
                             x[2 * i], x[2 * i + 1]);
            }
          } else {
            fmt::format_to(std::back_inserter(csv), "{:.17g}", t);
            for (int i = 0; i < static_cast<int>(x.size()); ++i) {
              fmt::format_to(std::back_inserter(csv), ",{:.17g}", x[i]);
            }
            fmt::format_to(std::back_inserter(csv), "\n");
          }
        }
        progress.Update(k);
      },
      &final_state);
  progress.Finish();

  nlohmann::json j;
  j["method"] = pbd::MethodName(summary.method);
  j["h"] = summary.h;
  j["steps"] = summary.counters.steps;
  j["final_time"] = summary.final_time;
  j["constraint_evaluations"] = summary.counters.constraint_evaluations;
  j["sweeps"] = summary.counters.sweeps;
  j["capped_steps"] = summary.counters.capped_steps;
  j["max_violation"] = summary.max_violation;
  j["wall_seconds"] = summary.wall_seconds;
  j["termination"] = summary.ok() ? "completed" : "non_finite";
  if (!summary.ok()) j["message"] = summary.message;
  if (problem.solution && summary.ok()) j["error"] = error;
  if (particles) {
    const auto& pc = dynamic_cast<const pbd::ParticleConstraints&>(*constraints);
    j["neighbour_list_builds"] = pc.neighbour_stats().neighbour_list_builds;
    j["candidate_pairs"] = pc.neighbour_stats().candidate_pairs;
  }
  j["settings"] = pbd_scenario.ToJson();
  j["scenario_file"] = args.scenario;
  out.WriteText("summary.json", j.dump(2) + "\n");
  out.WriteText("trajectory.csv", fmt::to_string(csv));
  RunPlotScript("plot_run.py", {out.Stage("trajectory.png").string(),
                                out.StagedPath("trajectory.csv").string(), pbd_scenario.kind,
                                fmt::format("{}", particles ? pbd_scenario.disks->radius : 0.0)});
  out.Commit();

  std::printf("%s\n", summary.BriefReport().c_str());
  if (problem.solution && summary.ok()) std::printf("error against the %s solution: %.6e\n",
                                                    particles ? "reference" : "exact", error);
  std::printf("wrote %s/summary.json, trajectory.csv, trajectory.png\n", out.dir().c_str());
  if (!summary.ok()) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n", summary.message.c_str());
    return 3;
  }
  return 0;
}

}  // namespace

void AddRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "Run one simulation of a scenario file");
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--set", args->overrides, "Override a scenario value: key=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder (default out/<scenario name>)");
  cmd->add_flag("--fix-overlaps", args->fix_overlaps,
                "Particle scenarios: project an overlapping initial state to a feasible one "
                "(repeated PBD sweeps) instead of rejecting it");
  cmd->callback([args] {
    const int code = Run(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace moreau::cli
