// The subcommands of the `moreau` tool. Each adds itself to the app; main() runs the one chosen.
#pragma once

#include <CLI/CLI.hpp>

namespace moreau::cli {

void AddRunCommand(CLI::App& app);
void AddStudyCommand(CLI::App& app);
void AddControlCommand(CLI::App& app);
void AddInspectCommand(CLI::App& app);

}  // namespace moreau::cli
