// Loops over slots on the engine's OpenMP threads. With one thread they run as plain loops: a
// parallel region sets up a team on every call, which small systems (the pbd adapter's 40 disks,
// rebuilt every few hundred sweeps) feel. Results do not depend on the thread count.
#pragma once

#include <algorithm>
#include <cstdint>

namespace moreau::particles::internal {

// f(i) for i in [begin, end), statically split among `threads` threads (Dynamic: one index at a
// time to the next free thread).
template <bool Dynamic = false, typename F>
void ParallelFor(int threads, std::int64_t begin, std::int64_t end, F&& f) {
  if (threads <= 1) {
    for (std::int64_t i = begin; i < end; ++i) f(i);
  } else if constexpr (Dynamic) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::int64_t i = begin; i < end; ++i) f(i);
  } else {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t i = begin; i < end; ++i) f(i);
  }
}

// max(*worst, f(i)) over i in [begin, end) into *worst, statically split among `threads` threads
// (a maximum is the same in any order, so the result does not depend on the thread count).
template <typename F>
void ParallelForMax(int threads, std::int64_t begin, std::int64_t end, double* worst, F&& f) {
  double w = *worst;
  if (threads <= 1) {
    for (std::int64_t i = begin; i < end; ++i) w = std::max(w, f(i));
  } else {
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : w)
    for (std::int64_t i = begin; i < end; ++i) w = std::max(w, f(i));
  }
  *worst = w;
}

// f() on a team of `threads` threads, or directly on this one (worksharing directives and
// barriers inside f then apply to a team of one).
template <typename F>
void InTeam(int threads, F&& f) {
  if (threads <= 1) {
    f();
    return;
  }
#pragma omp parallel num_threads(threads)
  f();
}

}  // namespace moreau::particles::internal
