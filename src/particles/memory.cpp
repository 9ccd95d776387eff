// The engine's memory estimate, checked before anything of size N is allocated.
#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/particles/engine.h"

namespace moreau::particles {

std::int64_t EstimateEngineBytes(int dimension, std::int64_t count) {
  const std::int64_t k = dimension == 3 ? 3 : 2;
  // Position buffers (current, predicted, list reference, forces, user copy, reorder scratch),
  // radius, mobility, ids, sort keys, path bounds, row starts, cells; neighbour half-lists at 16
  // (2D) or 32 (3D) candidates per particle of 5 bytes each.
  const std::int64_t per_particle = 8 * (6 * k + 8) + (k == 2 ? 80 : 160) + 48;
  if (count > (std::int64_t{1} << 62) / per_particle) return std::int64_t{1} << 62;
  return count * per_particle;
}

void CheckParticleMemory(int dimension, std::int64_t count, std::int64_t limit_bytes) {
  if (count < 0) throw InputError(fmt::format("must be ≥ 0 (got {})", count));
  if (count > std::int64_t{1} << 31) {
    throw InputError(fmt::format("{} particles is more than the engine's limit of 2^31", count));
  }
  CheckMemory(fmt::format("{} particles", count),
              static_cast<double>(EstimateEngineBytes(dimension, count)), limit_bytes);
}

}  // namespace moreau::particles
