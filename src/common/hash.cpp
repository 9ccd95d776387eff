#include "moreau/common/hash.h"

#include <cstring>

#include <fmt/format.h>

namespace moreau {

std::uint64_t HashDoubles(std::span<const double> values) {
  constexpr std::uint64_t kOffset = 14695981039346656037ULL;
  constexpr std::uint64_t kPrime = 1099511628211ULL;
  std::uint64_t hash = kOffset;
  for (const double v : values) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int byte = 0; byte < 8; ++byte) {
      hash ^= (bits >> (8 * byte)) & 0xFFU;
      hash *= kPrime;
    }
  }
  return hash;
}

std::string HashDoublesHex(std::span<const double> values) {
  return fmt::format("{:016x}", HashDoubles(values));
}

}  // namespace moreau
