// Internal: the optimal-control fill as one of fill.h's methods (FillMethod::kOcp).
#pragma once

#include <vector>

#include "moreau/mocap/fill.h"

namespace moreau::mocap::internal {

// Fills every gap of `gaps` with FillGapsOcp, the candidates being the baseline fills named by
// options.ocp.candidates (each computed by FillGap for the same gaps). One GapFill per gap, in
// input order: filled (the message says whether the optimal control or the prior filled it), or,
// when no candidate fills the gap, the first candidate's status. Throws InputError as
// FillGapsOcp does (e.g. a gap of a marker without partners).
std::vector<GapFill> FillGapsByOcp(const Recording& in, const std::vector<Gap>& gaps,
                                   const FillOptions& options);

}  // namespace moreau::mocap::internal
