// How moreau's programs make idle OpenMP threads wait, unless the user chose (docs/benchmarks.md,
// "OpenMP waiting").
//
// libgomp's default spins about 300000 pauses (≈ 5 ms on a 2.3 GHz Xeon) before sleeping: on a
// shared machine a spinning thread holds the core its partner needs, and a barrier can then cost
// a scheduler time slice. Passive waiting (no spin) avoids that, but then every parallel region
// and barrier wakes a sleeping thread, and waking a halted virtual CPU costs 60–360 µs on the
// machines we measured, more than a step of 10^5 particles spends in some regions. Spinning for
// about as long as one wake-up (kSpinCount pauses, ≈ 0.2 ms) before sleeping is within twice the
// better of the two in either case.
#pragma once

#include <unistd.h>

#include <cstdlib>

namespace moreau {

inline constexpr const char* kOpenMpSpinCount = "10000";

// libgomp reads its settings when it loads: unless OMP_WAIT_POLICY or GOMP_SPINCOUNT is set,
// sets GOMP_SPINCOUNT = kOpenMpSpinCount and runs this program again (argv as given). Call first
// thing in main; it returns at once when the user chose, or when the restart fails.
inline void RestartWithBoundedOpenMpSpin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) {
    return;
  }
  ::setenv("GOMP_SPINCOUNT", kOpenMpSpinCount, 1);
  ::execv("/proc/self/exe", argv);  // returns only on failure: go on with libgomp's default
}

}  // namespace moreau
