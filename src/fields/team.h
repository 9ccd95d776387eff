// How many threads a pass of the fields uses. Results do not depend on it: every line, row and
// partial sum is computed the same way on any thread.
#pragma once

#include <cstdint>

namespace moreau::fields::internal {

// Below this many voxels a pass runs on the calling thread: starting a team costs more than it
// saves there.
inline constexpr std::int64_t kParallelVoxels = 32768;

inline int TeamSize(int threads, std::int64_t voxels) {
  return voxels < kParallelVoxels ? 1 : threads;
}

}  // namespace moreau::fields::internal
