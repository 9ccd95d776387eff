// Helpers shared by the trajectory writers (internal).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "moreau/io/trajectory.h"

namespace moreau::io::internal {

// Throws InputError (message starting with `file`) unless the frame has dimension 2 or 3,
// count ≥ 0, non-null arrays when count > 0, and a finite time.
void ValidateFrame(const ParticleFrame& frame, const std::filesystem::path& file);

// Throws InputError naming `file` unless the directory that will hold it exists.
void CheckParentDirectory(const std::filesystem::path& file);

// `text` with &, <, >, " and ' replaced by XML entities.
std::string XmlEscape(std::string_view text);

// Shortest decimal text that reads back to the same double (fmt "{}").
std::string FormatDouble(double value);

// Appends the standard base64 (RFC 4648, with '=' padding) of `size` bytes at `data` to `out`.
void AppendBase64(const void* data, std::size_t size, std::string& out);

// Writes `content` to `file` (created or truncated). Throws std::runtime_error
// "cannot write FILE: reason" on any failure, including at close.
void WriteWholeFile(const std::filesystem::path& file, std::string_view content);

}  // namespace moreau::io::internal
