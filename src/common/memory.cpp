#include "moreau/common/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau {
namespace {

std::string ReadSmallFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The value in kB of the line "NAME: value kB" of a /proc file, in bytes.
std::optional<std::int64_t> KilobyteLine(std::string_view text, std::string_view name) {
  const std::size_t at = text.find(name);
  if (at == std::string_view::npos) return std::nullopt;
  std::istringstream line{std::string(text.substr(at + name.size()))};
  std::int64_t kilobytes = -1;
  line >> kilobytes;
  if (!line || kilobytes < 0) return std::nullopt;
  return kilobytes * 1024;
}

// The process's cgroup v2 folder ("0::/PATH" in /proc/self/cgroup), else the mount's root.
std::string CgroupFolder() {
  std::istringstream lines(ReadSmallFile("/proc/self/cgroup"));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("0::", 0) == 0) {
      const std::string folder = "/sys/fs/cgroup" + line.substr(3);
      if (std::ifstream(folder + "/memory.max")) return folder;
    }
  }
  return "/sys/fs/cgroup";
}

}  // namespace

std::optional<std::int64_t> ParseMemAvailable(std::string_view meminfo) {
  return KilobyteLine(meminfo, "MemAvailable:");
}

std::optional<std::int64_t> ParseCgroupBytes(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::int64_t bytes = -1;
  in >> bytes;
  if (!in || bytes < 0) return std::nullopt;
  return bytes;
}

MemoryLimit AvailableMemory() {
  std::vector<MemoryLimit> limits;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) {
    limits.push_back({static_cast<std::int64_t>(pages) * page, "physical memory"});
  }
  if (const auto available = ParseMemAvailable(ReadSmallFile("/proc/meminfo"))) {
    limits.push_back({*available, "MemAvailable"});
  }
  const std::string cgroup = CgroupFolder();
  if (const auto max = ParseCgroupBytes(ReadSmallFile(cgroup + "/memory.max"))) {
    const std::int64_t used =
        ParseCgroupBytes(ReadSmallFile(cgroup + "/memory.current")).value_or(0);
    limits.push_back({std::max<std::int64_t>(0, *max - used), "cgroup memory.max"});
  }
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY) {
    const std::int64_t mapped =
        KilobyteLine(ReadSmallFile("/proc/self/status"), "VmSize:").value_or(0);
    limits.push_back(
        {std::max<std::int64_t>(0, static_cast<std::int64_t>(address_space.rlim_cur) - mapped),
         "ulimit -v"});
  }
  MemoryLimit smallest{std::int64_t{1} << 62, "no limit found"};
  for (const MemoryLimit& l : limits) {
    if (l.bytes < smallest.bytes) smallest = l;
  }
  return smallest;
}

std::string FormatBytes(double bytes) {
  static constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  std::size_t unit = 0;
  while (std::abs(bytes) >= 1024.0 && unit + 1 < std::size(kUnits)) {
    bytes /= 1024.0;
    ++unit;
  }
  if (unit == 0) return fmt::format("{:.0f} B", bytes);
  return fmt::format("{:.{}f} {}", bytes,
                     std::abs(bytes) < 10.0    ? 2
                     : std::abs(bytes) < 100.0 ? 1
                                               : 0,
                     kUnits[unit]);
}

void CheckMemory(std::string_view what, double need_bytes, std::int64_t limit_bytes) {
  const MemoryLimit limit =
      limit_bytes > 0 ? MemoryLimit{limit_bytes, "the memory limit"} : AvailableMemory();
  if (need_bytes <= static_cast<double>(limit.bytes)) return;
  throw InputError(fmt::format("{} need about {}, more than the {} available ({})", what,
                               FormatBytes(need_bytes),
                               FormatBytes(static_cast<double>(limit.bytes)), limit.source));
}

}  // namespace moreau
