// Helpers shared by the fill methods (not installed).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "moreau/mocap/fill.h"

namespace moreau::mocap::internal {

// skipped_edge when the gap touches the first or last frame (no observed sample on one side).
std::optional<GapFill> EdgeStatus(const Recording& in, const Gap& gap);

// True when `marker` is observed at every frame first … last.
bool ObservedThroughout(const Recording& in, int marker, std::int64_t first, std::int64_t last);

}  // namespace moreau::mocap::internal
