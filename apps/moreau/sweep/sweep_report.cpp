#include "sweep/sweep_report.h"

#include <cstdio>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "output.h"
#include "signals.h"
#include "sweep/sweep_run.h"

namespace moreau::cli {
sweep::ResultsTable SweepTable(const SweepScenario& s,
                               const std::map<std::string, nlohmann::json>& journal, bool partial) {
  sweep::ResultsTable table;
  table.columns = {"run", "hash"};
  for (const sweep::Axis& axis : s.grid.axes) table.columns.push_back(axis.key);
  if (!s.grid.seeds.empty()) table.columns.push_back(s.grid.seed_key);
  table.columns.push_back("status");
  for (const std::string& key : s.collect) table.columns.push_back(key);
  table.columns.push_back("message");
  for (std::int64_t i = 0; i < s.grid.RunCount(); ++i) {
    const std::vector<sweep::Setting> settings = s.grid.Run(i);
    const std::string hash = sweep::RunHash(s.context, settings);
    const auto entry = journal.find(hash);
    if (entry == journal.end() && !partial) {
      throw InputError(fmt::format("run {} ({}) is missing from the journal", i, hash));
    }
    const nlohmann::json row =
        entry == journal.end() ? nlohmann::json{{"status", "not_run"}} : entry->second["row"];
    std::vector<nlohmann::json> cells{i, hash};
    for (const sweep::Setting& setting : settings) cells.push_back(LiteralCell(setting.value));
    cells.push_back(row.value("status", nlohmann::json()));
    for (const std::string& key : s.collect) cells.push_back(row.value(key, nlohmann::json()));
    cells.push_back(row.value("message", nlohmann::json()));
    table.rows.push_back(std::move(cells));
  }
  return table;
}

int ReportSweep(const SweepScenario& s, const sweep::ResultsTable& table, const SweepCounts& counts,
                const std::string& sweep_file, OutputDir& out) {
  const std::filesystem::path& dir = out.dir();
  const std::size_t status_column = 2 + s.grid.axes.size() + (s.grid.seeds.empty() ? 0 : 1);
  std::int64_t failed = 0, unfinished = 0;
  for (const auto& row : table.rows) {
    const nlohmann::json& status = row[status_column];
    if (RowInterrupted(status) || status == "not_run") {
      ++unfinished;
    } else if (!RowSucceeded(status)) {
      ++failed;
    }
  }
  const std::int64_t ran = counts.runs - counts.skipped;
  // Worker time not spent inside runs (reading, dispatch, journal, table, waiting at the end).
  const double overhead =
      ran > 0 ? (counts.ranks * counts.jobs * counts.total_seconds - counts.run_seconds) /
                    static_cast<double>(ran)
              : 0.0;
  const std::string stopped =
      unfinished == 0 ? ""
                      : fmt::format(
                            "stopped on request: {} of {} runs not finished (the same command runs "
                            "them)",
                            unfinished, counts.runs);
  nlohmann::json j =
      SummaryJson(unfinished == 0 ? Termination::kCompleted : Termination::kInterrupted, stopped,
                  counts.total_seconds);
  j["runs"] = counts.runs;
  j["runs_skipped"] = counts.skipped;
  j["runs_failed"] = failed;
  j["ranks"] = counts.ranks;
  j["jobs"] = counts.jobs;
  j["run_seconds"] = counts.run_seconds;
  j["overhead_seconds_per_run"] = overhead;
  j["sweep_file"] = sweep_file;
  j["settings"] = EchoSweepScenario(s);

  out.WriteText("results.csv", sweep::ResultsCsv(table));
  sweep::WriteResultsHdf5(out.Stage("results.h5"), table);
  out.WriteText("summary.json", JsonText(j) + "\n");
  out.Commit(WhenStopped::kPublish);  // beside the journal and the run folders
  std::printf(
      "sweep: %lld runs (%lld from the journal), %d rank%s × %d thread%s, %.2f s; "
      "%lld failed; overhead %.2f ms per run\n",
      static_cast<long long>(counts.runs), static_cast<long long>(counts.skipped), counts.ranks,
      counts.ranks == 1 ? "" : "s", counts.jobs, counts.jobs == 1 ? "" : "s", counts.total_seconds,
      static_cast<long long>(failed), 1e3 * overhead);
  std::printf("wrote %s/results.csv, results.h5, summary.json\n", dir.c_str());
  if (unfinished > 0) return ReportInterrupted(stopped);
  if (failed == 0) return 0;
  std::fprintf(stderr, "moreau: sweep: %lld of %lld runs failed (status and message in %s)\n",
               static_cast<long long>(failed), static_cast<long long>(counts.runs),
               (dir / "results.csv").c_str());
  return 3;
}

}  // namespace moreau::cli
