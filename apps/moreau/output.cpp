#include "output.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {

namespace fs = std::filesystem;

OutputDir::OutputDir(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) {
    throw InputError(fmt::format("{}: --out: cannot create the output folder ({})", dir_.string(),
                                 ec ? ec.message() : "not a folder"));
  }
  staging_ = dir_ / fmt::format(".moreau-staging-{}", static_cast<long>(::getpid()));
  fs::create_directories(staging_, ec);
  if (ec) {
    throw InputError(fmt::format("{}: --out: cannot write to the output folder ({})",
                                 dir_.string(), ec.message()));
  }
}

OutputDir::~OutputDir() {
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

fs::path OutputDir::Stage(const std::string& name) {
  names_.push_back(name);
  return staging_ / name;
}

void OutputDir::WriteText(const std::string& name, const std::string& content) {
  const fs::path path = Stage(name);
  std::ofstream out(path, std::ios::binary);
  out << content;
  out.close();
  if (!out) {
    throw InputError(fmt::format("{}: cannot write {}", dir_.string(), name));
  }
}

void OutputDir::Commit() {
  for (const std::string& name : names_) {
    const fs::path from = staging_ / name;
    if (!fs::exists(from)) continue;  // A figure whose script was skipped.
    std::error_code ec;
    if (fs::is_directory(from) && fs::exists(dir_ / name)) fs::remove_all(dir_ / name, ec);
    fs::rename(from, dir_ / name, ec);
    if (ec) {
      throw InputError(fmt::format("{}: cannot move {} into place ({})", dir_.string(), name,
                                   ec.message()));
    }
  }
  committed_ = true;
}

bool RunPlotScript(const std::string& script, const std::vector<std::string>& args) {
  std::string command = fmt::format("'{}' '{}/{}'", MOREAU_PYTHON, MOREAU_SCRIPTS_DIR, script);
  for (const std::string& a : args) command += fmt::format(" '{}'", a);
  command += " 1>&2";
  const int status = std::system(command.c_str());
  if (status != 0) {
    std::fprintf(stderr, "moreau: warning: %s failed; figures skipped (numbers are written)\n",
                 script.c_str());
    return false;
  }
  return true;
}

}  // namespace moreau::cli
