// A parameter grid: the runs of a sweep, each a list of scenario settings "key = value".
//
// A sweep varies scenario keys along axes (each a list of values) and repeats every point for a
// list of seeds. Axes are crossed (every combination; the last axis varies fastest) or zipped
// (the i-th run takes the i-th value of every axis); the seeds are crossed with the points and
// vary fastest of all. A run is identified by its settings, not by its place in the grid:
// RunHash() fingerprints them (with the sweep's context: base scenario, command, quantities),
// so a restarted or reordered sweep recognises the runs it has finished.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace moreau::sweep {

// One scenario setting of a run: a dotted key and its value as a TOML literal ("1.2", "\"pbd\"",
// "[0.5, 0.5]"), ready for a scenario override "key=value".
struct Setting {
  std::string key;
  std::string value;
};

// One axis: a dotted scenario key and its values (TOML literals), at least one.
struct Axis {
  std::string key;
  std::vector<std::string> values;
};

enum class Combination {
  kCross,  // every combination of the axes' values
  kZip,    // the i-th value of every axis together; all axes have the same length
};

// "cross", "zip"; Parse throws InputError "combine: …" for other names.
std::string_view CombinationName(Combination combination);
Combination ParseCombination(std::string_view name);

struct Grid {
  // The most runs a grid may have (points × seeds), and the memory a run's bookkeeping takes
  // (its settings, hash, journal entry and results row; checked by Validate against
  // moreau::AvailableMemory).
  static constexpr std::int64_t kMaxRuns = 10000000;
  static constexpr double kBytesPerRun = 2048.0;

  std::vector<Axis> axes;                         // in order; may be empty (one point)
  Combination combination = Combination::kCross;  // how the axes combine
  std::string seed_key = "problem.seed";          // the scenario key the seeds set
  std::vector<std::int64_t> seeds;                // empty: the scenario's own seed, one run

  // Throws InputError naming the field: an axis without values, a key twice (or an axis on the
  // seed key), zipped axes of different lengths, a seed twice, more than kMaxRuns runs or more
  // than the memory their bookkeeping needs.
  void Validate() const;
  // The number of points (product or common length of the axes) times the number of seeds.
  std::int64_t RunCount() const;
  // The settings of run `index` (0 ≤ index < RunCount()): the axes in order, then the seed.
  std::vector<Setting> Run(std::int64_t index) const;
};

// The run's identity: 16 hex digits of FNV-1a (64 bit) over `context` and the settings sorted
// by key, so the order of the axes does not matter.
std::string RunHash(std::string_view context, std::vector<Setting> settings);

}  // namespace moreau::sweep
