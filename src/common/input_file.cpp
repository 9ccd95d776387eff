#include "moreau/common/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"

namespace moreau {
namespace {

std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(mode)) return "is a character device, not a regular file";
  if (S_ISBLK(mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

// An open descriptor, closed on scope exit.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string NotAnInputFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    return errno == ENOENT ? "does not exist"
                           : fmt::format("cannot be read ({})", std::strerror(errno));
  }
  return S_ISREG(st.st_mode) ? "" : KindOf(st.st_mode);
}

std::string ReadInputFile(const std::string& path, std::int64_t max_bytes) {
  const auto fail = [&](const std::string& reason) {
    throw InputError(fmt::format("{}: {}", path, reason));
  };
  if (const std::string why = NotAnInputFile(path); !why.empty()) fail(why);
  // O_NONBLOCK: a FIFO put in the file's place after the check above cannot block the open.
  Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) fail(fmt::format("cannot be opened ({})", std::strerror(errno)));
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) fail(fmt::format("cannot be read ({})", std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) fail(KindOf(st.st_mode));
  const auto size = static_cast<std::int64_t>(st.st_size);
  if (max_bytes > 0 && size > max_bytes) {
    fail(fmt::format("the file has {} bytes, more than the {} accepted", size, max_bytes));
  }
  const MemoryLimit limit = AvailableMemory();
  if (limit.bytes > 0 && size > limit.bytes) {
    fail(fmt::format("the file ({}) is larger than the {} available ({})",
                     FormatBytes(static_cast<double>(size)),
                     FormatBytes(static_cast<double>(limit.bytes)), limit.source));
  }
  std::string content(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::read(file.fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(fmt::format("read failed ({})", std::strerror(errno)));
    if (n == 0) break;  // the file shrank while being read
    done += static_cast<std::size_t>(n);
  }
  content.resize(done);
  return content;
}

std::string_view WithoutByteOrderMark(std::string_view text) {
  constexpr std::string_view kMark = "\xEF\xBB\xBF";
  return text.substr(0, kMark.size()) == kMark ? text.substr(kMark.size()) : text;
}

}  // namespace moreau
