// An output folder that always holds exactly one complete result (docs/reliability.md).
//
// The files of a run are written into a staging folder beside DIR (DIR's parent, named
// .moreau-staging.PID.START.TOKEN.HOST) and published by Commit() in one rename: the staging
// folder takes DIR's place (renameat2 RENAME_EXCHANGE, or rename-aside-then-swap where the file
// system lacks it) and the previous DIR is removed. Until then DIR keeps what it held; if
// Commit() is never reached (an error, an exception) the destructor removes the staging folder.
// A process killed outside a run leaves its staging folder behind: the next OutputDir beside it
// removes the staging folders of dead processes on this host (PID and start time both checked).
//
// While an OutputDir is alive it holds an advisory lock (flock) on the file .DIR.moreau-lock
// beside DIR: a second run into the same folder is refused with an InputError (exit code 2).
// The destructor removes the staging folder and the lock file whatever ended the command (an
// error, a stop on request: signals.h).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace moreau::cli {

// How Commit() publishes.
enum class Publish {
  kReplace,  // the staging folder becomes DIR in one rename; the previous DIR is removed
  kMerge,    // each staged file is renamed into DIR, other files of DIR stay (a sweep's folder
             // with its journal)
};

// What Commit() does once a stop was requested (SIGINT/SIGTERM, signals.h).
enum class WhenStopped {
  kPublishNothing,  // throws Interrupted: a result only meaningful complete (control, fill-gaps)
  kPublish,         // publishes what was staged: complete, or marked interrupted by the command
};

class OutputDir {
 public:
  // Checks the path (length, not a file, with Publish::kReplace not a folder of someone else's
  // files: DIR must be empty or hold a summary.json or report.json), takes the lock, removes
  // stale staging folders and creates this run's. Creates DIR's parent folders if needed.
  // Throws InputError "DIR: --out: REASON".
  explicit OutputDir(std::filesystem::path dir, Publish publish = Publish::kReplace);
  // A staging folder in the system's temporary folder that is never published (a sweep run
  // without a run folder still stages its trajectory writers somewhere).
  static OutputDir Scratch();
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::filesystem::path& dir() const { return dir_; }

  // The staging path where NAME is to be written (absolute); it is published by Commit().
  std::filesystem::path Stage(const std::string& name);
  // Writes `content` as file `name`; InputError "DIR: cannot write NAME (REASON)" on failure
  // (a full disk: "No space left on device").
  void WriteText(const std::string& name, const std::string& content);
  // Runs write(the staged path of `name`); an InputError it throws names DIR/NAME instead of
  // the staging folder (a user never sees the staging name).
  void WriteWith(const std::string& name,
                 const std::function<void(const std::filesystem::path&)>& write);
  // Where an already staged NAME lies until Commit() (to read it back, e.g. for a figure).
  std::filesystem::path StagedPath(const std::string& name) const { return staging_ / name; }

  // Publishes the staged files (see Publish). Throws InputError when DIR cannot be written, and
  // Interrupted (publishing nothing) after a stop request unless `when_stopped` is kPublish.
  void Commit(WhenStopped when_stopped = WhenStopped::kPublishNothing);

 private:
  struct ScratchTag {};
  explicit OutputDir(ScratchTag);
  void ReleaseLock();
  void ReplaceTarget();
  void MergeIntoTarget();

  std::filesystem::path dir_;      // as given (for messages)
  std::filesystem::path target_;   // absolute, symlinks resolved
  std::filesystem::path staging_;  // beside target_
  std::vector<std::string> names_;
  Publish publish_ = Publish::kReplace;
  int lock_fd_ = -1;
  std::filesystem::path lock_path_;
  bool scratch_ = false;
};

// Runs a figure script with Debian's Python (MOREAU_PYTHON), by argument vector (posix_spawn: no
// shell, so no character of a path is ever interpreted). The script is looked up in
// <executable's folder>/../share/moreau/scripts (an installed tool), then in the source tree the
// tool was built from. Returns an empty string when the script ran and exited 0 (what it printed
// is passed on to stderr), else why not, in one line: the script not found, Python not
// startable, or "SCRIPT failed (exit status N: LAST LINE IT PRINTED)" (matplotlib missing, an
// error in the script). The caller checks that the figure was written.
std::string RunFigureScript(const std::string& script, const std::vector<std::string>& args);

// RunFigureScript, with one warning line on stderr when it fails ("moreau: warning: REASON;
// figures skipped (numbers are written)"): figures are an extra, never a reason to lose the
// numbers. Returns true when the script succeeded. After a stop request (signals.h) it runs
// nothing and returns false.
bool RunPlotScript(const std::string& script, const std::vector<std::string>& args);

// MESSAGE with every staging folder of this process replaced by the folder it stands for (an
// error from deep inside a writer names the staged file; the user knows only their folder).
std::string WithoutStagingNames(std::string message);

}  // namespace moreau::cli
