#include "output.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"

extern char** environ;

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kStagingPrefix = ".moreau-staging.";
constexpr std::string_view kOldPrefix = ".moreau-old.";

[[noreturn]] void Fail(const fs::path& dir, const std::string& reason) {
  throw InputError(fmt::format("{}: --out: {}", dir.string(), reason));
}

// The start time of process PID (clock ticks since boot, /proc/PID/stat field 22), −1 when there
// is no such process. With the PID it names one process for the machine's uptime.
long long ProcessStartTime(long pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t paren = stat.rfind(')');  // the command name may hold spaces and ')'
  if (!in.is_open() || paren == std::string::npos || paren + 2 > stat.size()) return -1;
  std::istringstream fields(stat.substr(paren + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 22) return std::stoll(field);
  }
  return -1;
}

std::string HostName() {
  char name[HOST_NAME_MAX + 1] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

// "PID.START.TOKEN.HOST": this process, and a random token so that no two folders collide.
std::string StagingTag() {
  const long pid = static_cast<long>(::getpid());
  std::random_device entropy;
  return fmt::format("{}.{}.{:08x}.{}", pid, ProcessStartTime(pid), entropy(), HostName());
}

// True for a staging (or set-aside) folder NAME whose process on this host is gone.
bool IsStale(const std::string& name) {
  std::string_view rest = name;
  if (rest.starts_with(kStagingPrefix)) {
    rest.remove_prefix(kStagingPrefix.size());
  } else if (rest.starts_with(kOldPrefix)) {
    rest.remove_prefix(kOldPrefix.size());
  } else {
    return false;
  }
  long pid = 0;
  long long start = 0;
  unsigned token = 0;
  int host_at = 0;
  const std::string fields(rest);
  if (std::sscanf(fields.c_str(), "%ld.%lld.%x.%n", &pid, &start, &token, &host_at) != 3 ||
      host_at == 0) {
    return false;
  }
  if (fields.substr(static_cast<std::size_t>(host_at)) != HostName()) return false;
  return ProcessStartTime(pid) != start;
}

void RemoveStaleStaging(const fs::path& parent) {
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    if (IsStale(it->path().filename().string())) {
      std::error_code ignored;
      fs::remove_all(it->path(), ignored);
    }
  }
}

// Refuses paths the system cannot hold, with the user's numbers (not a later ENAMETOOLONG).
void CheckPathLength(const fs::path& dir, const fs::path& absolute) {
  // Room for the names of the staging folder and the files in it.
  constexpr std::size_t kLongest = PATH_MAX - 128;
  if (absolute.string().size() > kLongest) {
    Fail(dir, fmt::format("the path is {} characters long; at most {} are allowed (the system's "
                          "limit is {})",
                          absolute.string().size(), kLongest, PATH_MAX));
  }
  for (const fs::path& part : absolute) {
    if (part.string().size() > NAME_MAX) {
      Fail(dir, fmt::format("a folder name is {} characters long; the system allows {}",
                            part.string().size(), NAME_MAX));
    }
  }
}

bool IsEmptyOrAResult(const fs::path& target) {
  std::error_code ec;
  if (fs::is_empty(target, ec)) return true;
  return fs::exists(target / "summary.json", ec) || fs::exists(target / "report.json", ec);
}

// flock(2) on PATH; the file is unlinked when released. Returns the descriptor, or −1 when
// another live process holds it (its PID, as it wrote it, in *holder).
int TakeLock(const fs::path& path, std::string* holder) {
  for (;;) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return -2;
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      char text[32] = {};
      const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
      *holder = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : "";
      ::close(fd);
      return -1;
    }
    // The file we locked may have been unlinked by its last holder meanwhile: then lock anew.
    struct stat opened {
    }, named{};
    if (::fstat(fd, &opened) == 0 && ::stat(path.c_str(), &named) == 0 &&
        opened.st_dev == named.st_dev && opened.st_ino == named.st_ino) {
      const std::string pid = std::to_string(::getpid());
      if (::ftruncate(fd, 0) == 0) {
        const ssize_t written = ::pwrite(fd, pid.data(), pid.size(), 0);
        (void)written;  // the PID only serves the message of a refused run
      }
      return fd;
    }
    ::close(fd);
  }
}

fs::path LockPath(const fs::path& target) {
  const std::string name = target.filename().string();
  if (name.size() + 13 <= NAME_MAX) return target.parent_path() / ("." + name + ".moreau-lock");
  std::uint64_t hash = 1469598103934665603ULL;  // FNV-1a of a name too long to repeat
  for (unsigned char c : name) hash = (hash ^ c) * 1099511628211ULL;
  return target.parent_path() / fmt::format(".moreau-lock.{:016x}", hash);
}


// Every occurrence of `from` in `text` replaced by `to`.
void ReplaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) {
    text.replace(at, from.size(), to);
  }
}

// Every staging folder this process made, with the folder it stands for: messages printed at
// the top (an error thrown from deep inside a writer) name the user's folder instead.
std::mutex staged_folders_mutex;
std::vector<std::pair<std::string, std::string>>& StagedFolders() {
  static std::vector<std::pair<std::string, std::string>> folders;
  return folders;
}

}  // namespace

OutputDir::OutputDir(fs::path dir, Publish publish) : dir_(std::move(dir)), publish_(publish) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(dir_, ec);
  if (ec) Fail(dir_, ec.message());
  CheckPathLength(dir_, absolute);
  target_ = fs::weakly_canonical(absolute, ec);
  if (ec) Fail(dir_, ec.message());
  if (!target_.has_filename()) target_ = target_.parent_path();
  if (target_ == target_.root_path()) Fail(dir_, "cannot replace the root folder");
  CheckPathLength(dir_, target_);
  if (fs::exists(target_, ec) && !fs::is_directory(target_, ec)) Fail(dir_, "not a folder");
  fs::create_directories(target_.parent_path(), ec);
  if (ec) Fail(dir_, fmt::format("cannot create the output folder ({})", ec.message()));

  lock_path_ = LockPath(target_);
  std::string holder;
  lock_fd_ = TakeLock(lock_path_, &holder);
  if (lock_fd_ == -2) Fail(dir_, fmt::format("cannot write beside it ({})", std::strerror(errno)));
  if (lock_fd_ == -1) {
    Fail(dir_, fmt::format("another moreau run{} is writing this folder; wait for it or choose "
                           "another --out",
                           holder.empty() ? "" : " (process " + holder + ")"));
  }
  try {
    if (publish_ == Publish::kReplace && fs::is_directory(target_, ec) &&
        !IsEmptyOrAResult(target_)) {
      Fail(dir_,
           "the folder holds files that are not a moreau result (no summary.json); "
           "choose an empty or new folder");
    }
    RemoveStaleStaging(target_.parent_path());
    staging_ = target_.parent_path() / (std::string(kStagingPrefix) + StagingTag());
    if (!fs::create_directory(staging_, ec) || ec) {
      Fail(dir_, fmt::format("cannot write beside it ({})", ec ? ec.message() : "name taken"));
    }
    const std::lock_guard<std::mutex> lock(staged_folders_mutex);
    StagedFolders().emplace_back(staging_.string(), dir_.string());
  } catch (...) {
    ReleaseLock();  // no destructor for a constructor that throws
    throw;
  }
}

OutputDir OutputDir::Scratch() { return OutputDir(ScratchTag{}); }

OutputDir::OutputDir(ScratchTag) : dir_(fs::temp_directory_path()), scratch_(true) {
  RemoveStaleStaging(dir_);
  staging_ = dir_ / (std::string(kStagingPrefix) + StagingTag());
  std::error_code ec;
  if (!fs::create_directory(staging_, ec) || ec) {
    throw InputError(fmt::format("{}: cannot create a scratch folder ({})", dir_.string(),
                                 ec ? ec.message() : "name taken"));
  }
}

OutputDir::~OutputDir() {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  ReleaseLock();
}

void OutputDir::ReleaseLock() {
  if (lock_fd_ < 0) return;
  ::unlink(lock_path_.c_str());  // while still held: see TakeLock
  ::close(lock_fd_);
  lock_fd_ = -1;
}

fs::path OutputDir::Stage(const std::string& name) {
  names_.push_back(name);
  return staging_ / name;
}

void OutputDir::WriteText(const std::string& name, const std::string& content) {
  const fs::path path = Stage(name);
  std::FILE* file = std::fopen(path.c_str(), "wb");
  bool written = file != nullptr && std::fwrite(content.data(), 1, content.size(), file) ==
                                        content.size();
  int error = written ? 0 : errno;
  if (file != nullptr && std::fclose(file) != 0 && written) {
    written = false;
    error = errno;
  }
  if (!written) {
    throw InputError(fmt::format("{}: cannot write {} ({})", dir_.string(), name,
                                 std::strerror(error != 0 ? error : EIO)));
  }
}

void OutputDir::WriteWith(const std::string& name,
                          const std::function<void(const fs::path&)>& write) {
  const fs::path path = Stage(name);
  try {
    write(path);
  } catch (const InputError& e) {
    std::string message = e.what();
    ReplaceAll(message, path.string(), (dir_ / name).string());
    throw InputError(message);
  }
}

void OutputDir::Commit(WhenStopped when_stopped) {
  if (scratch_) throw std::logic_error("OutputDir::Commit on a scratch folder");
  if (when_stopped == WhenStopped::kPublishNothing && StopRequested()) {
    throw Interrupted(fmt::format("stopped on request before {} was published", dir_.string()));
  }
  if (publish_ == Publish::kReplace) {
    ReplaceTarget();
  } else {
    MergeIntoTarget();
  }
}

void OutputDir::ReplaceTarget() {
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    fs::rename(staging_, target_, ec);
    if (ec) Fail(dir_, fmt::format("cannot publish the result ({})", ec.message()));
    staging_.clear();
    return;
  }
  // One rename swaps the two folders; staging_ then names the previous result.
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS) {
      Fail(dir_, fmt::format("cannot publish the result ({})", std::strerror(errno)));
    }
    // No exchange on this file system: set the previous result aside, then rename.
    const fs::path old = target_.parent_path() / (std::string(kOldPrefix) + StagingTag());
    fs::rename(target_, old, ec);
    if (!ec) fs::rename(staging_, target_, ec);
    if (ec) Fail(dir_, fmt::format("cannot publish the result ({})", ec.message()));
    staging_ = old;
  }
  fs::remove_all(staging_, ec);  // what is left (if anything) goes with the next run beside it
  staging_.clear();
}

void OutputDir::MergeIntoTarget() {
  std::error_code ec;
  fs::create_directories(target_, ec);
  if (ec) Fail(dir_, fmt::format("cannot create the output folder ({})", ec.message()));
  for (const std::string& name : names_) {
    const fs::path from = staging_ / name;
    if (!fs::exists(from)) continue;  // A figure whose script was skipped.
    if (fs::is_directory(from) && fs::exists(target_ / name)) fs::remove_all(target_ / name, ec);
    fs::rename(from, target_ / name, ec);
    if (ec) Fail(dir_, fmt::format("cannot move {} into place ({})", name, ec.message()));
  }
}

namespace {

// The folder of this executable (/proc/self/exe), empty when unknown.
fs::path ExecutableFolder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

// SCRIPT beside an installed tool (<bin>/../share/moreau/scripts), else in the source tree it was
// built from; empty when neither has it. *looked: the folders searched, for the warning.
fs::path FindScript(const std::string& script, std::string* looked) {
  std::vector<fs::path> folders;
  const fs::path exe_folder = ExecutableFolder();
  if (!exe_folder.empty())
    folders.push_back((exe_folder / MOREAU_INSTALLED_SCRIPTS).lexically_normal());
  folders.emplace_back(MOREAU_SCRIPTS_DIR);
  for (const fs::path& folder : folders) {
    std::error_code ec;
    if (fs::is_regular_file(folder / script, ec)) return folder / script;
    *looked += (looked->empty() ? "" : ", ") + folder.string();
  }
  return {};
}

// What a child process did: its wait status (−1 when it could not be started, errno in
// `start_error`) and everything it wrote to stdout and stderr.
struct ChildRun {
  int status = -1;
  int start_error = 0;
  std::string output;
};

// Runs ARGV (argv[0] a path) with its stdout and stderr captured through one pipe.
ChildRun SpawnAndWait(const std::vector<std::string>& argv) {
  ChildRun run;
  std::vector<char*> pointers;
  for (const std::string& a : argv) pointers.push_back(const_cast<char*>(a.c_str()));
  pointers.push_back(nullptr);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    run.start_error = errno;
    return run;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  pid_t pid = 0;
  run.start_error = ::posix_spawn(&pid, pointers[0], &actions, nullptr, pointers.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  char buffer[4096];
  while (run.start_error == 0) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n > 0) {
      run.output.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  if (run.start_error != 0) return run;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return run;
  }
  run.status = status;
  return run;
}

// The last non-blank line of TEXT (a traceback's last line names the error), empty if none.
std::string LastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  const auto first = last.find_first_not_of(" \t");
  return first == std::string::npos ? std::string() : last.substr(first);
}

}  // namespace

std::string RunFigureScript(const std::string& script, const std::vector<std::string>& args) {
  std::string looked;
  const fs::path path = FindScript(script, &looked);
  if (path.empty()) return fmt::format("figure script {} not found (looked in {})", script, looked);
  std::vector<std::string> argv = {MOREAU_PYTHON, path.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  const ChildRun run = SpawnAndWait(argv);
  if (run.status == -1) {
    return fmt::format("cannot run {} ({})", MOREAU_PYTHON, std::strerror(run.start_error));
  }
  if (WIFEXITED(run.status) && WEXITSTATUS(run.status) == 0) {
    std::fputs(run.output.c_str(), stderr);  // the script's own notes, as it wrote them
    return {};
  }
  const std::string how = WIFEXITED(run.status)
                              ? fmt::format("exit status {}", WEXITSTATUS(run.status))
                              : fmt::format("signal {}", WTERMSIG(run.status));
  const std::string last = LastLine(run.output);
  return fmt::format("{} failed ({}{}{})", script, how, last.empty() ? "" : ": ", last);
}

bool RunPlotScript(const std::string& script, const std::vector<std::string>& args) {
  if (StopRequested()) return false;  // stopping: the numbers only
  const std::string failure = RunFigureScript(script, args);
  if (failure.empty()) return true;
  std::fprintf(stderr, "moreau: warning: %s; figures skipped (numbers are written)\n",
               failure.c_str());
  return false;
}

std::string WithoutStagingNames(std::string message) {
  const std::lock_guard<std::mutex> lock(staged_folders_mutex);
  for (const auto& [staged, dir] : StagedFolders()) ReplaceAll(message, staged, dir);
  return message;
}

}  // namespace moreau::cli
