// Reading a file a user names (a scenario, a recording, a gap list, a checkpoint).
//
// Only regular files are read: a FIFO could block the tool for ever, and a device such as
// /dev/zero or /dev/urandom never ends. The file is opened without blocking, checked with fstat
// on the open descriptor, and read to its end; its size is checked against what may still be
// allocated (AvailableMemory, memory.h) before the bytes are.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace moreau {

// Why `path` cannot be read as an input file: "does not exist", "is a directory", "is a FIFO
// (named pipe), not a regular file", "is a character device, not a regular file", …; "" when
// it is a regular file that can be opened. Follows symbolic links.
std::string NotAnInputFile(const std::string& path);

// The whole file. Throws InputError "PATH: REASON" for NotAnInputFile's reasons, a read error,
// and a file whose size exceeds max_bytes (> 0) or what may still be allocated.
std::string ReadInputFile(const std::string& path, std::int64_t max_bytes = 0);

// `text` without a leading UTF-8 byte-order mark (EF BB BF).
std::string_view WithoutByteOrderMark(std::string_view text);

}  // namespace moreau
