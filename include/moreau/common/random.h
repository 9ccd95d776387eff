// Seeded generators, the same bits on every platform and thread count.
//
// SplitMix64: a small sequential generator for initial states (random sequential addition,
// random placements). Philox4x32-10: a counter-based generator; a value is a pure function of
// (counter, key), so noise for (seed, particle id, step) needs no per-thread state.
#pragma once

#include <array>
#include <cstdint>

namespace moreau {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next();
  double Uniform01();  // in [0, 1), 53 random bits
 private:
  std::uint64_t state_;
};

// Philox4x32-10 of the 128-bit counter with a 64-bit key (Salmon et al., SC'11).
std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> counter,
                                        std::array<std::uint32_t, 2> key);

}  // namespace moreau
