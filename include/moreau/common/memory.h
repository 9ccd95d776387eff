// The memory a run may still allocate, and byte counts written for people.
//
// A size check before a large allocation compares an estimate with AvailableMemory(): the
// smallest of the address space left under RLIMIT_AS (`ulimit -v`, less what the process already
// maps), the cgroup v2 limit (memory.max less memory.current), MemAvailable of /proc/meminfo and
// the physical memory. Whatever cannot be read is left out. CheckMemory throws InputError with
// both numbers in readable units and the limit that binds.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace moreau {

// An allocation failed (std::bad_alloc) while doing what the message names; the CLI prints it on
// one line and exits with code 3.
class OutOfMemoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MemoryLimit {
  std::int64_t bytes = 0;  // what may still be allocated
  std::string source;      // "ulimit -v", "cgroup memory.max", "MemAvailable", "physical memory"
};

// The binding limit now (see above); bytes ≥ 0.
MemoryLimit AvailableMemory();

// "812 B", "3.4 KiB", "120 MiB", "1.5 GiB", "2.0 TiB": three significant digits, binary units.
std::string FormatBytes(double bytes);

// Throws InputError "WHAT need about NEED, more than the LIMIT available (SOURCE)" (WHAT: a
// plural, "200 particles") when
// need_bytes > limit_bytes, where limit_bytes ≤ 0 means AvailableMemory().
void CheckMemory(std::string_view what, double need_bytes, std::int64_t limit_bytes = 0);

// Parsers of the files AvailableMemory reads (exposed for tests): the "MemAvailable:" line of
// /proc/meminfo in bytes; a cgroup v2 memory.max or memory.current value ("max" → empty).
std::optional<std::int64_t> ParseMemAvailable(std::string_view meminfo);
std::optional<std::int64_t> ParseCgroupBytes(std::string_view text);

}  // namespace moreau
