#include "mocap/file_util.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <set>
#include <system_error>

#include "moreau/common/error.h"
#include "moreau/common/input_file.h"

namespace moreau::mocap::internal {

void Fail(const std::filesystem::path& file, std::string_view field, std::string_view reason) {
  throw InputError(fmt::format("{}: {}: {}", file.string(), field, reason));
}

std::string ReadWholeFile(const std::filesystem::path& file) {
  if (const std::string why = NotAnInputFile(file.string()); !why.empty()) Fail(file, "file", why);
  return ReadInputFile(file.string());
}

void WriteFileAtomically(const std::filesystem::path& file, std::string_view content) {
  const std::filesystem::path parent =
      file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(parent, ec)) {
    Fail(file, "file", fmt::format("directory {} does not exist", parent.string()));
  }
  const std::filesystem::path temporary =
      parent / fmt::format(".{}.tmp-{}", file.filename().string(), ::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) Fail(file, "file", fmt::format("cannot be written ({})", std::strerror(errno)));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) {
      const int error = errno != 0 ? errno : EIO;
      std::filesystem::remove(temporary, ec);
      Fail(file, "file", fmt::format("write failed ({})", std::strerror(error)));
    }
  }
  std::filesystem::rename(temporary, file, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    Fail(file, "file", fmt::format("cannot be renamed into place ({})", ec.message()));
  }
}

std::string GeneratedLabel(std::size_t index, std::string_view prefix) {
  return fmt::format("{}{}", prefix, index + 1);
}

void MakeLabelsUnique(std::vector<std::string>& labels, const std::filesystem::path& file,
                      std::string_view field, std::vector<std::string>& warnings,
                      std::string_view prefix) {
  std::set<std::string> used(labels.begin(), labels.end());
  std::set<std::string> seen;
  std::vector<std::string> changes;
  for (std::size_t m = 0; m < labels.size(); ++m) {
    std::string& label = labels[m];
    if (!label.empty() && seen.insert(label).second) continue;
    const std::string base = label.empty() ? GeneratedLabel(m, prefix) : label;
    std::string unique = base;
    for (int k = 2; used.count(unique) != 0; ++k) unique = fmt::format("{}_{}", base, k);
    changes.push_back(fmt::format("{} → {}", label.empty() ? "(empty)" : label, unique));
    used.insert(unique);
    seen.insert(unique);
    label = unique;
  }
  if (!changes.empty()) {
    warnings.push_back(fmt::format("{}: {}: labels renamed to be unique: {}", file.string(), field,
                                   fmt::join(changes, ", ")));
  }
}

std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return lines;
}

std::vector<std::string_view> SplitFields(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  for (;;) {
    const std::size_t end = line.find(separator);
    fields.push_back(line.substr(0, end));
    if (end == std::string_view::npos) return fields;
    line.remove_prefix(end + 1);
  }
}

std::string_view TrimBlanks(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

bool ParseNumber(std::string_view text, double& value) {
  text = TrimBlanks(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

std::string ToLower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string FormatNumber(double value) { return fmt::format("{}", value); }

}  // namespace moreau::mocap::internal
