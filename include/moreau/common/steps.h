// Step counting for fixed-step time integration on [0, T].
#pragma once

#include <cstdint>

namespace moreau {

// n = T / h when T > 0, h > 0 and T / h is a whole number (to a relative 1e-9); n ≥ 1. Throws
// InputError "T must be > 0 (got …)", "h must be > 0 (got …)" or
// "T / h must be a whole number (T = …, h = …)".
std::int64_t StepCount(double T, double h);

}  // namespace moreau
