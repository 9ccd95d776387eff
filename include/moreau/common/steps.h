// Step counting for fixed-step time integration on [0, T].
#pragma once

#include <cstdint>

namespace moreau {

// The most steps one run may take (10^9: hours for a single particle, and a bound that keeps
// every step count exact in a double and in an int64).
inline constexpr std::int64_t kMaxSteps = 1'000'000'000;

// n = T / h when T > 0, h > 0 and T / h is a whole number (to a relative 1e-9); 1 ≤ n ≤ kMaxSteps.
// Throws InputError "T must be > 0 (got …)", "h must be > 0 (got …)",
// "T / h = … steps is more than the 1000000000 allowed (T = …, h = …)" or
// "T / h must be a whole number (T = …, h = …)".
std::int64_t StepCount(double T, double h);

}  // namespace moreau
