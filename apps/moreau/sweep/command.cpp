// `moreau sweep SWEEP.toml [--set key=value ...] [--out DIR] [--jobs J]`: a parameter sweep or
// ensemble of runs of one command (docs/sweeps.md): sweep_scenario → the runs, handed out by
// sweep::Dispatch over MPI ranks (under mpirun/srun) or a local pool, each appended to its
// rank's journal (DIR/journal.jsonl, DIR/journal.rank<k>.jsonl) as it finishes → sweep_report
// (results.csv, results.h5, summary.json). Runs already in a journal (by the hash of their
// settings) are not run again. The first run of the grid is read and set up before anything is
// written, so a bad key or value stops the sweep with exit code 2; the exit code is 3 when any
// run of the table failed.
#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "commands.h"
#include "moreau/common/stopwatch.h"
#include "moreau/sweep/dispatch.h"
#include "moreau/sweep/journal.h"
#include "sweep/sweep_report.h"
#include "sweep/sweep_run.h"
#include "sweep/sweep_scenario.h"

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

struct SweepArgs : ScenarioArgs {
  int jobs = 1;
};

// The grid positions whose hash the journal lacks.
std::vector<std::int64_t> RunsToDo(const SweepScenario& s,
                                   const std::map<std::string, nlohmann::json>& journal) {
  std::vector<std::int64_t> todo;
  for (std::int64_t i = 0; i < s.grid.RunCount(); ++i) {
    if (journal.count(sweep::RunHash(s.context, s.grid.Run(i))) == 0) todo.push_back(i);
  }
  return todo;
}

int Sweep(const SweepArgs& args) {
  const sweep::MpiSession mpi;
  const Stopwatch clock;
  Scenario file = Scenario::Load(args.scenario, args.overrides);
  const SweepScenario s = ReadSweepScenario(file);
  file.CheckAllKeysUsed();
  if (args.jobs < 1) file.Fail("--jobs", fmt::format("must be ≥ 1 (got {})", args.jobs));
  CheckFirstRun(s, file);  // a typo in a key or a bad value: exit 2 before anything is written
  const fs::path dir = args.OutDir();
  fs::create_directories(dir);  // on every rank: the folder may be local to a node
  SweepCounts counts{s.grid.RunCount(), 0, mpi.size(), args.jobs, 0.0, 0.0};
  std::vector<std::int64_t> todo;
  if (mpi.rank() == 0) {
    todo = RunsToDo(s, sweep::Journal::ReadFolder(dir));
    counts.skipped = counts.runs - static_cast<std::int64_t>(todo.size());
  }
  std::optional<sweep::Journal> journal;  // this rank's, opened at its first finished run
  const std::vector<nlohmann::json> entries = sweep::Dispatch(
      mpi, todo, args.jobs, [&](std::int64_t index) { return SweepEntry(s, index, dir); },
      [&](const nlohmann::json& entry) {
        if (!journal) journal.emplace(sweep::Journal::PathFor(dir, mpi.rank()));
        journal->Append(entry);
        const nlohmann::json& row = entry["row"];
        if (!RowSucceeded(row["status"])) {
          std::fprintf(stderr, "moreau: sweep: run %lld (%s) %s: %s\n",
                       static_cast<long long>(entry["index"].get<std::int64_t>()),
                       entry["hash"].get<std::string>().c_str(),
                       row["status"].get<std::string>().c_str(),
                       row["message"].get<std::string>().c_str());
        }
      });
  if (mpi.rank() != 0) return 0;
  journal.reset();
  // The journals rank 0 sees, and this invocation's entries of every rank (the other ranks'
  // journals may lie on their own nodes' disks).
  std::map<std::string, nlohmann::json> finished = sweep::Journal::ReadFolder(dir);
  for (const nlohmann::json& entry : entries) {
    counts.run_seconds += entry["seconds"].get<double>();
    finished[entry["hash"].get<std::string>()] = entry;
  }
  const sweep::ResultsTable table = SweepTable(s, finished);
  counts.total_seconds = clock.Seconds();
  return ReportSweep(s, table, counts, args.scenario, dir);
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  CLI::App* cmd = AddScenarioCommand(
      app, "sweep", "Run a parameter sweep or ensemble (under mpirun: over MPI ranks)", args.get(),
      "out/<sweep file name>", [args] { return Sweep(*args); });
  cmd->add_option("--jobs", args->jobs, "Runs at a time in each process (threads; default 1)");
}

}  // namespace moreau::cli
