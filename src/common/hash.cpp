#include "moreau/common/hash.h"

#include <cstring>

#include <fmt/format.h>

namespace moreau {

namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

}  // namespace

std::uint64_t HashBytes(std::string_view bytes) {
  std::uint64_t hash = kFnvOffset;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= kFnvPrime;
  }
  return hash;
}

std::uint64_t HashDoubles(std::span<const double> values) {
  std::uint64_t hash = kFnvOffset;
  for (const double v : values) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int byte = 0; byte < 8; ++byte) {
      hash ^= (bits >> (8 * byte)) & 0xFFU;
      hash *= kFnvPrime;
    }
  }
  return hash;
}

std::string HashDoublesHex(std::span<const double> values) {
  return fmt::format("{:016x}", HashDoubles(values));
}

}  // namespace moreau
