// `moreau study SCENARIO.toml --methods pbd,pngs,pgs,penalty[:gamma] --h 0.1,0.05,... [--out DIR]`:
// error against the exact (sliding) or reference (disks) solution for every method and step size,
// the observed orders, and the convergence and precision–work figures. The runs go through the
// sweep machinery (StudyGrid, sweep::Dispatch): `--jobs` threads, and MPI ranks under mpirun.
#include <memory>

#include <fmt/format.h>

#include "commands.h"
#include "moreau/common/error.h"
#include "run/pbd_scenario.h"
#include "study/study_report.h"
#include "study/study_run.h"
#include "sweep/sweep_run.h"

namespace moreau::cli {
namespace {

struct StudyArgs : ScenarioArgs {
  StudyRequest request;
  int jobs = 1;
};

int Study(const StudyArgs& args) {
  std::optional<Scenario> scenario;
  std::optional<PbdScenario> pbd_scenario;
  std::optional<PbdStudyPlan> plan;
  CheckBeforeMpi([&] {
    scenario.emplace(Scenario::Load(args.scenario, args.overrides));
    pbd_scenario.emplace(ReadPbdScenario(*scenario));
    scenario->CheckAllKeysUsed();
    sweep::CheckJobs(args.jobs);
    plan.emplace(MakeStudyPlan(args.request, *pbd_scenario));
  });
  const sweep::MpiSession mpi;
  return RunOnRanks(mpi, [&] {
    const std::optional<PbdStudyResult> result =
        RunPbdStudy(mpi, *scenario, *pbd_scenario, *plan, args.jobs);
    if (!result) return 0;  // not rank 0: rank 0 writes
    return ReportPbdStudy(*pbd_scenario, *plan, *result, args.scenario, args.OutDir("_study"));
  });
}

}  // namespace

void AddStudyCommand(CLI::App& app) {
  auto args = std::make_shared<StudyArgs>();
  CLI::App* cmd = AddScenarioCommand(
      app, "study", "Convergence and precision-work study over methods and step sizes", args.get(),
      "out/<scenario name>_study", [args] { return Study(*args); });
  cmd->add_option("--methods", args->request.methods, "pbd,pngs,pgs,penalty[:gamma]")
      ->delimiter(',')
      ->required();
  cmd->add_option("--h", args->request.hs, "Step sizes, e.g. 0.1,0.05,0.025")
      ->delimiter(',')
      ->required();
  cmd->add_option("--fit-points", args->request.fit_points,
                  "How many of the smallest step sizes the observed order is fitted over")
      ->capture_default_str();
  cmd->add_option("--jobs", args->jobs, "Runs at a time in each process (threads; default 1)");
}

}  // namespace moreau::cli
