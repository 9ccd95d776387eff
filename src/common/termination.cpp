#include "moreau/common/termination.h"

#include <array>
#include <string>
#include <utility>

#include "moreau/common/enum_names.h"

namespace moreau {

namespace {

constexpr EnumNames<Termination, 8> kNames{{
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

std::string_view ToString(Termination termination) { return EnumName(kNames, termination); }

Termination ParseTermination(std::string_view name) {
  return ParseEnumName(kNames, name, "termination");
}

}  // namespace moreau
