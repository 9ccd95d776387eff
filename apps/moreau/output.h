// An output folder that never holds half-written results.
//
// Files are written into a hidden staging folder inside DIR and moved into DIR by Commit(), each
// by an atomic rename, only once everything succeeded. If Commit() is never reached (an error, an
// exception) the destructor removes the staging folder and DIR keeps what it had before.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace moreau::cli {

class OutputDir {
 public:
  explicit OutputDir(std::filesystem::path dir);
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::filesystem::path& dir() const { return dir_; }

  // The staging path where NAME is to be written; it is moved to DIR/NAME by Commit().
  std::filesystem::path Stage(const std::string& name);
  void WriteText(const std::string& name, const std::string& content);
  // Where an already staged NAME lies until Commit() (to read it back, e.g. for a figure).
  std::filesystem::path StagedPath(const std::string& name) const { return staging_ / name; }

  // Moves every staged file into DIR. Throws InputError when DIR cannot be written.
  void Commit();

 private:
  std::filesystem::path dir_;
  std::filesystem::path staging_;
  std::vector<std::string> names_;
  bool committed_ = false;
};

// Runs a figure script from MOREAU_SCRIPTS_DIR with Debian's Python. Returns false (after one
// warning line on stderr) when Python or matplotlib is missing or the script fails: figures are
// an extra, never a reason to lose the numbers.
bool RunPlotScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace moreau::cli
