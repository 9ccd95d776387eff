// The tridiagonal solves of grid lines (src/fields/line_solves.cpp), by LOD's Step: every line is
// solved by the same operations in the same order whatever its neighbours, its group and the copy
// of the loops (portable or AVX2) that runs it, so the bits depend on neither the thread count nor
// the processor.
#pragma once

#include <cstdint>

#include "moreau/fields/field_set.h"

namespace moreau::fields::internal {

// x lines solved in one group by SolveXLinesOn (declared in field_set.h): four AVX2 registers of
// four lines each.
inline constexpr int kXLinesTogether = 16;

// `width` lines side by side, line q's value i at c[q + i·stride], n values each, with the widest
// copy this processor runs.
void SolveStridedLines(const LineSolve& f, double* c, std::int64_t n, std::int64_t stride,
                       std::int64_t width);

}  // namespace moreau::fields::internal
