// The fuzz targets' inputs as files: the readers under test take a path, so each input is
// written to one per-process temporary file first.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace moreau::fuzz {

// Writes the input to $TMPDIR (or /tmp)/moreau-fuzz-PID.SUFFIX and returns that path.
inline std::string WriteInputFile(const std::uint8_t* data, std::size_t size,
                                  const std::string& suffix) {
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("moreau-fuzz-" + std::to_string(::getpid()) + suffix))
                                      .string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace moreau::fuzz
