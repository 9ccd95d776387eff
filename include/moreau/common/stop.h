// A request to stop, for the whole process: the application sets it (the `moreau` tool from its
// SIGINT/SIGTERM handlers; the library never installs a handler) and the library's long loops
// poll it between steps, Newton iterations, trials and runs (docs/reliability.md, "Interrupting
// a run").
//
// Polled by: pbd::Simulate (every step), control::SolveNewton (every iteration), mocap::FillGaps
// (every gap), mocap::EvaluateFillMethods (every trial: the trials not started are skipped and
// the summary ends kInterrupted) and sweep::Dispatch (no run is handed out after a request).
// Where a loop cannot return a partial result it throws Interrupted, so every object on the way
// out is destroyed as after any other exception.
#pragma once

#include <stdexcept>

namespace moreau {

// Thrown by a loop that stops on request ("stopped on request …": what() says where). Never
// thrown out of an OpenMP parallel region.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Records a request to stop (REASON ≠ 0: the signal number, or any code the caller chooses; the
// first request is kept) and returns whether it was the first. Async-signal-safe: one lock-free
// atomic.
bool RequestStop(int reason) noexcept;
// The reason of the first request, 0 while there is none.
int StopReason() noexcept;
// True once a stop was requested. Cheap (a relaxed atomic load): polled every step.
inline bool StopRequested() noexcept { return StopReason() != 0; }
// Forgets the request (tests only).
void ClearStopRequest() noexcept;

}  // namespace moreau
