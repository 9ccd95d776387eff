// SIGINT and SIGTERM for the `moreau` tool (docs/reliability.md, "Interrupting a run").
//
// main() installs the handlers once. Outside a StopScope a signal ends the process at once
// (exit 128 + signal, one line on stderr): nothing is published, the output folder keeps what it
// held, and the staging folder left behind is removed by the next run beside it. Inside a
// StopScope (the time loops of `moreau run`) the signal only sets a flag: the loop finishes its
// current step and stops, and the command publishes what is complete, marked "interrupted", and
// exits 128 + signal (130 for SIGINT, 143 for SIGTERM). A second signal ends the process at once.
#pragma once

#include <string>

#include <fmt/format.h>

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

// True once SIGINT or SIGTERM arrived (inside a StopScope): the loops' "should stop" check; a
// library loop's observer returns false then, and the loop ends after the step just taken.
bool StopRequested();

// SUMMARY (of a loop its observer stopped after STEP, at time T) marked kInterrupted, with the
// message of a stop on request.
template <class Summary>
Summary InterruptedSummary(Summary summary, long long step, double t) {
  summary.termination = Termination::kInterrupted;
  summary.message = fmt::format("stopped on request after step {} (t = {:g})", step, t);
  return summary;
}

// After a run that ended interrupted: prints "moreau: interrupted by SIGINT: MESSAGE" on stderr
// and returns the exit code, 128 + the signal (130 when no signal is recorded).
int ReportInterrupted(const std::string& message);

// The exit code of a run that ended with `termination`: 0 on success, ReportInterrupted's when
// interrupted, 3 after a numerical failure (printed on stderr with `message`).
int RunExitCode(Termination termination, const std::string& message);

}  // namespace moreau::cli
