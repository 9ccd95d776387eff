// `moreau sweep SWEEP.toml [--set key=value ...] [--out DIR] [--jobs J]`: a parameter sweep or
// ensemble of runs of one command (docs/sweeps.md): sweep_scenario → the runs, handed out by
// sweep::Dispatch over MPI ranks (under mpirun/srun) or a local pool, each appended to
// DIR/journal.jsonl as it finishes → sweep_report (results.csv, results.h5, summary.json).
// Runs already in the journal (by the hash of their settings) are not run again.
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
  const fs::path dir = args.OutDir();
  const fs::path journal_path = dir / "journal.jsonl";
  SweepCounts counts{s.grid.RunCount(), 0, mpi.size(), args.jobs, 0.0, 0.0};
  std::vector<std::int64_t> todo;
  std::optional<sweep::Journal> journal;
  if (mpi.rank() == 0) {
    fs::create_directories(dir);
    todo = RunsToDo(s, sweep::Journal::Read(journal_path));
    counts.skipped = counts.runs - static_cast<std::int64_t>(todo.size());
    journal.emplace(journal_path);
  }
  sweep::Dispatch(
      mpi, todo, args.jobs, [&](std::int64_t index) { return SweepEntry(s, index, dir); },
      [&](const nlohmann::json& entry) {
        journal->Append(entry);
        counts.run_seconds += entry["seconds"].get<double>();
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
  const sweep::ResultsTable table = SweepTable(s, sweep::Journal::Read(journal_path));
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
