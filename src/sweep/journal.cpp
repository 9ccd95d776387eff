#include "moreau/sweep/journal.h"

#include <algorithm>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"

namespace moreau::sweep {

Journal::Journal(std::filesystem::path path) : path_(std::move(path)) {
  bool ends_mid_line = false;  // a line cut short by a kill: the next entry starts a new line
  if (std::ifstream in(path_, std::ios::binary | std::ios::ate); in && in.tellg() > 0) {
    in.seekg(-1, std::ios::end);
    ends_mid_line = in.get() != '\n';
  }
  file_ = std::fopen(path_.c_str(), "ab");
  if (file_ == nullptr) {
    throw InputError(
        fmt::format("{}: cannot open the sweep journal for appending", path_.string()));
  }
  if (ends_mid_line) std::fputc('\n', file_);
}

Journal::~Journal() {
  if (file_ != nullptr) std::fclose(file_);
}

void Journal::Append(const nlohmann::json& entry) {
  const std::string line = JsonText(entry, -1) + "\n";
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0) {
    throw InputError(fmt::format("{}: cannot write the sweep journal", path_.string()));
  }
}

std::map<std::string, nlohmann::json> Journal::Read(const std::filesystem::path& path) {
  std::map<std::string, nlohmann::json> entries;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    nlohmann::json entry = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!entry.is_object() || !entry.contains("hash") || !entry["hash"].is_string()) continue;
    const std::string hash = entry["hash"].get<std::string>();
    entries[hash] = std::move(entry);
  }
  return entries;
}

std::filesystem::path Journal::PathFor(const std::filesystem::path& dir, int rank) {
  return dir /
         (rank == 0 ? std::string("journal.jsonl") : fmt::format("journal.rank{}.jsonl", rank));
}

std::map<std::string, nlohmann::json> Journal::ReadFolder(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> paths;
  std::error_code absent;  // no folder yet: no journal
  for (const auto& file : std::filesystem::directory_iterator(dir, absent)) {
    const std::string name = file.path().filename().string();
    if (name.starts_with("journal") && name.ends_with(".jsonl")) paths.push_back(file.path());
  }
  std::sort(paths.begin(), paths.end());
  std::map<std::string, nlohmann::json> entries;
  for (const auto& path : paths) entries.merge(Read(path));
  return entries;
}

}  // namespace moreau::sweep
