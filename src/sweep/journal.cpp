#include "moreau/sweep/journal.h"

#include <fstream>

#include <fmt/format.h>

#include "moreau/common/error.h"

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
  const std::string line = entry.dump() + "\n";
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

}  // namespace moreau::sweep
