// A fingerprint of an array of doubles, for regression checks on bits (tests, benchmarks,
// summary.json): two arrays hash equal when their raw bytes are equal (−0 ≠ +0, NaN payloads
// count).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace moreau {

// 64-bit FNV-1a over the bytes of `bytes`, in order.
std::uint64_t HashBytes(std::string_view bytes);

// 64-bit FNV-1a over the little-endian bytes of the values, in order.
std::uint64_t HashDoubles(std::span<const double> values);

// The same as 16 lower-case hex digits ("cbf29ce484222325" for an empty array).
std::string HashDoublesHex(std::span<const double> values);

}  // namespace moreau
