#include "moreau/common/termination.h"

#include <array>
#include <string>
#include <utility>

#include "moreau/common/error.h"

namespace moreau {

namespace {

constexpr std::array<std::pair<Termination, std::string_view>, 8> kNames{{
    {Termination::kCompleted, "completed"},
    {Termination::kConverged, "converged"},
    {Termination::kMaxIterations, "max_iterations"},
    {Termination::kLineSearchFailed, "line_search_failed"},
    {Termination::kSingularJacobian, "singular_jacobian"},
    {Termination::kDiverged, "diverged"},
    {Termination::kNonFinite, "non_finite"},
    {Termination::kInterrupted, "interrupted"},
}};

}  // namespace

std::string_view ToString(Termination termination) {
  for (const auto& [value, name] : kNames) {
    if (value == termination) return name;
  }
  MOREAU_ASSERT(false);
}

Termination ParseTermination(std::string_view name) {
  for (const auto& [value, name_of] : kNames) {
    if (name_of == name) return value;
  }
  throw InputError("unknown termination '" + std::string(name) + "'");
}

}  // namespace moreau
