// `moreau sweep SWEEP.toml [--set key=value ...] [--out DIR] [--jobs J]`: a parameter sweep or
// ensemble of runs of one command (docs/sweeps.md): sweep_scenario → the runs, handed out by
// sweep::Dispatch over MPI ranks (under mpirun/srun) or a local pool, each appended to its
// rank's journal (DIR/journal.jsonl, DIR/journal.rank<k>.jsonl) as it finishes → sweep_report
// (results.csv, results.h5, summary.json). Runs already in a journal (by the hash of their
// settings) are not run again. Every run of the grid is read and checked, and the output folder
// checked and locked, before any run, so a bad key or value or folder stops the sweep with exit
// code 2; the exit code is 3 when any run of the table failed, 128 + signal after a stop on
// request (the runs stopped are not journaled: the same command redoes them).
#include <cstdio>
#include <memory>
#include <optional>
#include <system_error>

#include <fmt/format.h>

#include "commands.h"
#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/sweep/dispatch.h"
#include "moreau/sweep/journal.h"
#include "output.h"
#include "signals.h"
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

// The sweep proper, on every rank, after every input check.
int RunSweep(const SweepScenario& s, const SweepArgs& args, const sweep::MpiSession& mpi,
             const Stopwatch& clock) {
  const fs::path dir = args.OutDir();
  // Rank 0 checks DIR (not the root, not a file, writable, its path length), holds its lock for
  // the whole sweep (a second sweep into DIR is refused) and stages the table in it at the end.
  std::optional<OutputDir> out;
  if (mpi.rank() == 0) out.emplace(dir, Publish::kMerge);
  std::error_code error;
  fs::create_directories(dir, error);  // on every rank: the folder may be local to a node
  if (error) {
    throw InputError(
        fmt::format("{}: --out: cannot create the folder ({})", dir.string(), error.message()));
  }
  SweepCounts counts{s.grid.RunCount(), 0, mpi.size(), args.jobs, 0.0, 0.0};
  std::vector<std::int64_t> todo;
  std::optional<sweep::Journal> journal;  // this rank's (rank 0's opened before any run)
  if (mpi.rank() == 0) {
    todo = RunsToDo(s, sweep::Journal::ReadFolder(dir));
    counts.skipped = counts.runs - static_cast<std::int64_t>(todo.size());
    journal.emplace(sweep::Journal::PathFor(dir, 0));
  }
  const std::vector<nlohmann::json> entries = sweep::Dispatch(
      mpi, todo, args.jobs, [&](std::int64_t index) { return SweepEntry(s, index, dir); },
      [&](const nlohmann::json& entry) {
        const nlohmann::json& row = entry["row"];
        if (RowInterrupted(row["status"])) return;  // not finished: the next sweep redoes it
        if (!journal) journal.emplace(sweep::Journal::PathFor(dir, mpi.rank()));
        journal->Append(entry);
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
  // journals may lie on their own nodes' disks); the runs stopped on request as such.
  std::map<std::string, nlohmann::json> finished = sweep::Journal::ReadFolder(dir);
  for (const nlohmann::json& entry : entries) {
    counts.run_seconds += entry["seconds"].get<double>();
    if (!RowInterrupted(entry["row"]["status"]) ||
        finished.count(entry["hash"].get<std::string>()) == 0) {
      finished[entry["hash"].get<std::string>()] = entry;
    }
  }
  const sweep::ResultsTable table = SweepTable(s, finished, /*partial=*/StopRequested());
  counts.total_seconds = clock.Seconds();
  return ReportSweep(s, table, counts, args.scenario, *out);
}

int Sweep(const SweepArgs& args) {
  const Stopwatch clock;
  std::optional<SweepScenario> s;
  CheckBeforeMpi([&] {
    Scenario file = Scenario::Load(args.scenario, args.overrides);
    s = ReadSweepScenario(file);
    file.CheckAllKeysUsed();
    try {
      sweep::CheckJobs(args.jobs);
    } catch (const InputError& e) {
      file.Fail("--jobs", e.reason());
    }
    CheckRuns(*s, file);  // a typo in a key or a bad value: exit 2 before anything is written
  });
  const sweep::MpiSession mpi;
  return RunOnRanks(mpi, [&] { return RunSweep(*s, args, mpi, clock); });
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
