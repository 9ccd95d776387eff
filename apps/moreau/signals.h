// SIGINT and SIGTERM for the `moreau` tool (docs/reliability.md, "Interrupting a run").
//
// main() installs the handlers once; each command that writes an output folder runs its body
// through RunStoppable. Inside it the first signal only records a stop request
// (moreau/common/stop.h): the loops stop at their next step, Newton iteration, trial or run —
// a particle or population run, a sweep, a study and an evaluation publish what is complete,
// marked "interrupted"; the other commands throw Interrupted, which unwinds through every
// OutputDir (its destructor removes the staging folder and the lock) — and the tool exits
// 128 + signal (130 for SIGINT, 143 for SIGTERM) after one line on stderr. Outside
// RunStoppable (parsing the command line, `inspect`, `keys`), and on a second signal anywhere,
// the signal ends the process at once.
#pragma once

#include <functional>
#include <string>

#include <fmt/format.h>

#include "moreau/common/stop.h"
#include "moreau/common/termination.h"

namespace moreau::cli {

// Installs the SIGINT/SIGTERM handlers (main() only).
void InstallStopHandlers();

// While one is alive, SIGINT/SIGTERM set the stop flag instead of ending the process.
class StopScope {
 public:
  StopScope();
  ~StopScope();
  StopScope(const StopScope&) = delete;
  StopScope& operator=(const StopScope&) = delete;
};

// Runs a command's body in a StopScope and returns its exit code: ReportInterrupted's when the
// body ends with Interrupted ("…; no result published") or returns 0 after a signal came (its
// result was complete and is published).
int RunStoppable(const std::function<int()>& run);

// SUMMARY (of a loop its observer stopped after STEP, at time T) marked kInterrupted, with the
// message of a stop on request.
template <class Summary>
Summary InterruptedSummary(Summary summary, long long step, double t) {
  summary.termination = Termination::kInterrupted;
  summary.message = fmt::format("stopped on request after step {} (t = {:g})", step, t);
  return summary;
}

// After a run that ended interrupted: prints "moreau: interrupted by SIGINT: MESSAGE" on stderr
// (unless QuietStopMessages) and returns the exit code, 128 + the signal (130 when no signal is
// recorded).
int ReportInterrupted(const std::string& message);

// No "interrupted" line from this process (an MPI rank other than 0: rank 0 speaks for the job,
// and a rank that mpirun ends after another rank's error has nothing true to add).
void QuietStopMessages();

// The exit code of a run that ended with `termination`: 0 on success, ReportInterrupted's when
// interrupted, 3 after a numerical failure (printed on stderr with `message`).
int RunExitCode(Termination termination, const std::string& message);

}  // namespace moreau::cli
