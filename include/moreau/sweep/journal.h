// The journal of a sweep: one JSON object per finished run, one line each, appended and flushed
// as each run finishes, so an interrupted sweep loses at most the runs in flight.
//
// An entry is {"hash": RunHash, "seconds": run time, "row": {column: value, …}}. Reading skips a
// last line cut short by a kill (it does not parse) and keeps the last entry of a hash that
// appears twice.
#pragma once

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace moreau::sweep {

class Journal {
 public:
  // Opens PATH for appending (created when absent; a last line cut short is ended first, so
  // the next entry starts a line of its own). Throws InputError when it cannot.
  explicit Journal(std::filesystem::path path);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  // Appends `entry` (an object with a string "hash") as one line and flushes it to the system.
  // Throws InputError when the write fails.
  void Append(const nlohmann::json& entry);

  // The entries of PATH by hash (empty when PATH is absent). Lines that are not a JSON object
  // with a string "hash" are skipped.
  static std::map<std::string, nlohmann::json> Read(const std::filesystem::path& path);

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

}  // namespace moreau::sweep
