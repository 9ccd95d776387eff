// File helpers shared by the recording readers and writers (internal).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace moreau::mocap::internal {

// Throws InputError "FILE: FIELD: reason".
[[noreturn]] void Fail(const std::filesystem::path& file, std::string_view field,
                       std::string_view reason);

// The whole file; InputError naming it when it is missing, a directory or unreadable.
std::string ReadWholeFile(const std::filesystem::path& file);

// Writes `content` under a temporary name beside `file`, then renames it to `file`, so that
// `file` is complete or untouched. InputError naming the file on any failure.
void WriteFileAtomically(const std::filesystem::path& file, std::string_view content);

// The label given to marker `index` (0-based) when the file names none: "<prefix><index + 1>"
// ("M1", …; C3D uses BTK's "uname*1", …).
std::string GeneratedLabel(std::size_t index, std::string_view prefix = "M");

// Replaces empty labels by GeneratedLabel(their index, prefix) and repeated ones by "LABEL_2",
// "LABEL_3", …, appending one warning naming the file and `field` when anything changed.
void MakeLabelsUnique(std::vector<std::string>& labels, const std::filesystem::path& file,
                      std::string_view field, std::vector<std::string>& warnings,
                      std::string_view prefix = "M");

// The lines of `text` (LF or CRLF), without their line ends.
std::vector<std::string_view> SplitLines(std::string_view text);

// The fields of `line` separated by `separator` (an empty line gives one empty field).
std::vector<std::string_view> SplitFields(std::string_view line, char separator);

// `text` without surrounding spaces and tabs.
std::string_view TrimBlanks(std::string_view text);

// Parses a whole decimal number (surrounding blanks allowed); false when `text` is not one.
bool ParseNumber(std::string_view text, double& value);

// `text` in lower case (ASCII).
std::string ToLower(std::string_view text);

// Shortest decimal text that reads back to the same double.
std::string FormatNumber(double value);

}  // namespace moreau::mocap::internal
