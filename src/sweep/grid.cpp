#include "moreau/sweep/grid.h"

#include <algorithm>
#include <array>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/enum_names.h"
#include "moreau/common/error.h"
#include "moreau/common/hash.h"
#include "moreau/common/memory.h"

namespace moreau::sweep {
namespace {

constexpr std::array<std::pair<Combination, std::string_view>, 2> kCombinationNames{{
    {Combination::kCross, "cross"},
    {Combination::kZip, "zip"},
}};

// The points, at most Grid::kMaxRuns + 1 (a larger product stops there: never an overflow).
std::int64_t PointCount(const Grid& grid) {
  if (grid.axes.empty()) return 1;
  if (grid.combination == Combination::kZip) {
    return static_cast<std::int64_t>(grid.axes.front().values.size());
  }
  std::int64_t count = 1;
  for (const Axis& axis : grid.axes) {
    const auto n = static_cast<std::int64_t>(axis.values.size());
    count = n != 0 && count > Grid::kMaxRuns / n ? Grid::kMaxRuns + 1 : count * n;
  }
  return count;
}

}  // namespace

std::string_view CombinationName(Combination combination) {
  return EnumName(kCombinationNames, combination);
}

Combination ParseCombination(std::string_view name) {
  return ParseEnumName(kCombinationNames, name, "combine");
}

void Grid::Validate() const {
  std::set<std::string, std::less<>> keys;
  for (const Axis& axis : axes) {
    if (axis.values.empty()) {
      throw InputError(fmt::format("axes.{}: an axis needs at least one value", axis.key));
    }
    if (!keys.insert(axis.key).second) {
      throw InputError(fmt::format("axes.{}: the key is varied twice", axis.key));
    }
    if (!seeds.empty() && axis.key == seed_key) {
      throw InputError(
          fmt::format("axes.{}: the seeds set this key already (seeds, seed_key)", axis.key));
    }
    if (combination == Combination::kZip && axis.values.size() != axes.front().values.size()) {
      throw InputError(
          fmt::format("axes.{}: zipped axes need the same number of values ({} here, {} for {})",
                      axis.key, axis.values.size(), axes.front().values.size(), axes.front().key));
    }
  }
  const std::int64_t points = PointCount(*this);
  const auto seed_count = std::max<std::int64_t>(1, static_cast<std::int64_t>(seeds.size()));
  if (points > kMaxRuns / seed_count) {
    throw InputError(fmt::format("axes: {} points × {} seeds is more than the {} runs a sweep may have",
                                 points > kMaxRuns ? fmt::format("more than {}", kMaxRuns)
                                                   : std::to_string(points),
                                 seed_count, kMaxRuns));
  }
  CheckMemory(fmt::format("{} runs", points * seed_count),
              kBytesPerRun * static_cast<double>(points * seed_count));
  std::set<std::int64_t> seen;
  for (const std::int64_t seed : seeds) {
    if (!seen.insert(seed).second) throw InputError(fmt::format("seeds: {} is listed twice", seed));
  }
}

std::int64_t Grid::RunCount() const {
  return PointCount(*this) * std::max<std::int64_t>(1, static_cast<std::int64_t>(seeds.size()));
}

std::vector<Setting> Grid::Run(std::int64_t index) const {
  const auto seed_count = std::max<std::int64_t>(1, static_cast<std::int64_t>(seeds.size()));
  std::int64_t point = index / seed_count;
  std::vector<Setting> settings(axes.size());
  for (std::size_t a = axes.size(); a-- > 0;) {  // the last axis varies fastest
    const auto n = static_cast<std::int64_t>(axes[a].values.size());
    const std::int64_t i = combination == Combination::kZip ? point : point % n;
    settings[a] = {axes[a].key, axes[a].values[static_cast<std::size_t>(i)]};
    if (combination == Combination::kCross) point /= n;
  }
  if (!seeds.empty()) {
    settings.push_back(
        {seed_key, fmt::format("{}", seeds[static_cast<std::size_t>(index % seed_count)])});
  }
  return settings;
}

std::string RunHash(std::string_view context, std::vector<Setting> settings) {
  std::sort(settings.begin(), settings.end(),
            [](const Setting& a, const Setting& b) { return a.key < b.key; });
  std::string text(context);
  text += '\n';
  for (const Setting& s : settings) text += fmt::format("{}={}\n", s.key, s.value);
  return fmt::format("{:016x}", HashBytes(text));
}

}  // namespace moreau::sweep
