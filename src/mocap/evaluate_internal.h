// The evaluation's parts shared by its two sources (not installed).
#pragma once

#include <cstdint>
#include <vector>

#include "moreau/mocap/evaluate.h"

namespace moreau::mocap::internal {

// Per gap length (lengths[g] frames, options.gap_seconds[g]) and method, the statistics of the
// rows of that method and length (EvaluationStatistics), ordered by gap length, then method.
std::vector<EvaluationStatistics> EvaluationStatisticsOf(const std::vector<EvaluationRow>& rows,
                                                         const EvaluationOptions& options,
                                                         const std::vector<std::int64_t>& lengths);

}  // namespace moreau::mocap::internal
