// How a simulation or a solver ended: one type for every summary in moreau.
//
// Simulations (pbd::Simulate, particles::Engine::Run) end kCompleted or kNonFinite (or
// kInterrupted when an observer asks to stop); iterative solvers (control::SolveNewton,
// continuation) end kConverged or with the reason they stopped. IsSuccess() is the one success
// predicate every summary's ok() forwards to. ToString/ParseTermination give the names used in
// summary.json and by the Python package.
#pragma once

#include <string_view>

namespace moreau {

enum class Termination {
  kCompleted,         // a simulation ran to its final time
  kConverged,         // a solver met its tolerance
  kMaxIterations,     // a solver stopped at its iteration cap
  kLineSearchFailed,  // no step along the Newton direction reduced the residual
  kSingularJacobian,  // the linear solve failed
  kDiverged,          // a solver's iterate or residual became non-finite or blew up
  kNonFinite,         // a simulation's state became non-finite (the last good state is kept)
  kInterrupted,       // an observer or a signal asked to stop early
};

// "completed", "converged", "max_iterations", "line_search_failed", "singular_jacobian",
// "diverged", "non_finite", "interrupted".
std::string_view ToString(Termination termination);
// Throws InputError for an unknown name.
Termination ParseTermination(std::string_view name);

// True for kCompleted and kConverged.
constexpr bool IsSuccess(Termination termination) {
  return termination == Termination::kCompleted || termination == Termination::kConverged;
}

}  // namespace moreau
