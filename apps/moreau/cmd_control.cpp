// Placeholder: the `control` subcommand (issue 3) replaces this file.
#include "commands.h"

namespace moreau::cli {
void AddControlCommand(CLI::App& app) { (void)app; }
}  // namespace moreau::cli
