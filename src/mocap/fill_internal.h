// Helpers shared by the fill methods (not installed).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "moreau/mocap/fill.h"

namespace moreau::mocap::internal {

// skipped_edge when the gap touches the first or last frame (no observed sample on one side).
std::optional<GapFill> EdgeStatus(const Recording& in, const Gap& gap);

// True when `marker` is observed at every frame first … last.
bool ObservedThroughout(const Recording& in, int marker, std::int64_t first, std::int64_t last);

// The summary of filling `gaps` (already checked against `in`) one after the other, gap i by
// fill_gap(i), each timed, the method named `method`; *out becomes `in` with every filled
// sample set (out may be &in). Leaves settings and total_seconds to the caller.
FillSummary SummarizeFills(const Recording& in, const std::vector<Gap>& gaps,
                           std::string_view method,
                           const std::function<GapFill(std::size_t)>& fill_gap, Recording* out);

}  // namespace moreau::mocap::internal
