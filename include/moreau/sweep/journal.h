// The journal of a sweep: one JSON object per finished run, one line each, appended and flushed
// as each run finishes, so an interrupted sweep loses at most the runs in flight.
//
// An entry is {"hash": RunHash, "seconds": run time, "row": {column: value, …}}. Reading skips a
// last line cut short by a kill (it does not parse) and keeps the last entry of a hash that
// appears twice.
//
// Under MPI every rank keeps a journal of its own in the sweep's folder (rank 0: journal.jsonl,
// rank k: journal.rank<k>.jsonl), so no rank waits for another to record a run; a restart reads
// them all, whatever the number of ranks that wrote them.
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

  // The journal of `rank` in the sweep folder `dir`.
  static std::filesystem::path PathFor(const std::filesystem::path& dir, int rank);
  // The entries of every journal in `dir` (journal.jsonl, journal.rank<k>.jsonl), read in the
  // order of their names (a hash in two: the first); empty when there is none.
  static std::map<std::string, nlohmann::json> ReadFolder(const std::filesystem::path& dir);

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

}  // namespace moreau::sweep
