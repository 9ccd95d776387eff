// moreau: constrained motion of particles and spring networks, from the command line.
#include <unistd.h>

#include <cstdio>
#include <string>
#include <cstdlib>
#include <exception>
#include <new>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/common/openmp_wait.h"
#include "output.h"
#include "signals.h"

int main(int argc, char** argv) {
  moreau::RestartWithBoundedOpenMpSpin(argv);  // OpenMP waiting (openmp_wait.h)
  moreau::cli::InstallStopHandlers();
  CLI::App app{"moreau " MOREAU_VERSION
               ": position-based dynamics and optimal control of particles and spring networks"};
  app.require_subcommand(1);
  app.set_version_flag("--version", MOREAU_VERSION);
  moreau::cli::AddRunCommand(app);
  moreau::cli::AddStudyCommand(app);
  moreau::cli::AddControlCommand(app);
  moreau::cli::AddInspectCommand(app);
  moreau::cli::AddFillGapsCommand(app);
  moreau::cli::AddEvaluateGapsCommand(app);
  moreau::cli::AddSweepCommand(app);
  moreau::cli::AddMeasureCommand(app);
  moreau::cli::AddKeysCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // A subcommand that finished with a non-zero status.
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const moreau::InputError& e) {
    const std::string message = moreau::cli::WithoutStagingNames(e.what());
    std::fprintf(stderr, "moreau: error: %s\n", message.c_str());
    return 2;
  } catch (const moreau::NumericalError& e) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n", e.what());
    return 3;
  }
  // Out of memory (the size checks estimate before allocating; this is what they missed).
  catch (const moreau::OutOfMemoryError& e) {
    std::fprintf(stderr, "moreau: out of memory: %s\n", e.what());
    return 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(
        stderr, "moreau: out of memory: an allocation failed while running `moreau %s`\n",
        app.get_subcommands().empty() ? "" : app.get_subcommands().front()->get_name().c_str());
    return 3;
  } catch (const std::exception& e) {
    const std::string message = moreau::cli::WithoutStagingNames(e.what());
    std::fprintf(stderr, "moreau: error: %s\n", message.c_str());
    return 1;
  }
  return 0;
}
