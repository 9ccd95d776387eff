// The engine's memory estimate, checked before anything of size N is allocated.
#include <unistd.h>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/engine.h"

namespace moreau::particles {

std::int64_t EstimateEngineBytes(int dimension, std::int64_t count) {
  const std::int64_t k = dimension == 3 ? 3 : 2;
  // Position buffers (current, predicted, list reference, forces, user copy), radius, mobility,
  // ids, sort keys, path bounds, row starts, cells; neighbour half-lists at 16 (2D) or 32 (3D)
  // candidates per particle of 5 bytes each.
  const std::int64_t per_particle = 8 * (5 * k + 8) + (k == 2 ? 80 : 160) + 48;
  if (count > (std::int64_t{1} << 62) / per_particle) return std::int64_t{1} << 62;
  return count * per_particle;
}

void CheckParticleMemory(int dimension, std::int64_t count, std::int64_t limit_bytes) {
  if (count < 0) throw InputError(fmt::format("count must be ≥ 0 (got {})", count));
  if (count > std::int64_t{1} << 31) {
    throw InputError(
        fmt::format("count: {} particles is more than the engine's limit of 2^31", count));
  }
  std::int64_t limit = limit_bytes;
  if (limit <= 0) {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page = sysconf(_SC_PAGE_SIZE);
    limit = pages > 0 && page > 0 ? static_cast<std::int64_t>(pages) * page : std::int64_t{1} << 62;
  }
  const std::int64_t need = EstimateEngineBytes(dimension, count);
  if (need > limit) {
    constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
    throw InputError(
        fmt::format("count: {} particles need about {:.1f} GiB, more than the {:.1f} GiB available",
                    count, static_cast<double>(need) / kGiB, static_cast<double>(limit) / kGiB));
  }
}

}  // namespace moreau::particles
