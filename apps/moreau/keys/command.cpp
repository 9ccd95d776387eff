// `moreau keys [COMMAND] [--markdown]`: every scenario key of every command (or of one), with its
// type, default, range, unit and help, from the same field tables that read, check and echo the
// settings; `--markdown` writes the reference docs/keys.md holds.
#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "control/control_scenario.h"
#include "evaluate_gaps/evaluate_gaps_scenario.h"
#include "field_table.h"
#include "fill_gaps/fill_gaps_scenario.h"
#include "moreau/particles/population.h"
#include "run/particles_scenario.h"
#include "run/pbd_scenario.h"
#include "sweep/sweep_scenario.h"

namespace moreau::cli {
namespace {

struct KeySection {
  std::string command;  // run, study, control, fill-gaps, evaluate-gaps, sweep
  std::string title;    // "run: problem.kind = \"sliding\""
  std::vector<KeyRow> rows;
};

std::vector<KeySection> AllSections() {
  std::vector<KeySection> out;
  for (const char* kind : {"sliding", "disks"}) {
    for (const char* command : {"run", "study"}) {
      out.push_back({command, fmt::format("{}: problem.kind = \"{}\"", command, kind),
                     PbdFields(kind).Rows(PbdScenario{})});
    }
  }
  out.push_back({"run", "run: problem.kind = \"particles\" (and agent-based models, [[types]])",
                 ParticleFields().Rows(ParticleScenario{})});
  out.push_back({"run", "run: [[types]] (each agent type; --set types.<name>.<key>)",
                 ListRows(particles::AgentType::Fields(), "types.<name>")});
  for (const char* model : {"oscillator", "arm", "network"}) {
    out.push_back({"control", fmt::format("control: model = \"{}\"", model),
                   ControlFields(model).Rows(ControlScenario{})});
  }
  out.push_back(
      {"fill-gaps", "fill-gaps (--set or --scenario)", FillGapsFields().Rows(FillGapsSettings{})});
  out.push_back({"evaluate-gaps", "evaluate-gaps (--set or --scenario)",
                 EvaluateGapsFields().Rows(EvaluateGapsSettings{})});
  out.push_back({"sweep", "sweep (the sweep file)", SweepKeys()});
  return out;
}

std::string Cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

void PrintSection(const KeySection& section, bool markdown) {
  if (markdown) {
    fmt::print(
        "## {}\n\n| key | type | default | range | unit | help |\n|---|---|---|---|---|---|\n",
        section.title);
    for (const KeyRow& r : section.rows) {
      fmt::print("| `{}` | {} | {} | {} | {} | {} |\n", r.key, Cell(r.type), Cell(r.default_value),
                 Cell(r.range), Cell(r.unit), Cell(r.help));
    }
    fmt::print("\n");
    return;
  }
  fmt::print("{}\n", section.title);
  for (const KeyRow& r : section.rows) {
    fmt::print("  {:<34} {:<20} {:<14} {:<16} {:<8} {}\n", r.key, r.type, r.default_value, r.range,
               r.unit, r.help);
  }
  fmt::print("\n");
}

struct KeysArgs {
  std::string command;
  bool markdown = false;
};

void PrintKeys(const KeysArgs& args) {
  const std::vector<KeySection> sections = AllSections();
  bool any = false;
  if (args.markdown) {
    fmt::print(
        "# Scenario keys\n\nEvery key of every command: in a scenario file (TOML tables), "
        "after `--set`, and in a sweep's `[set]` and `[axes]`. Written by `moreau keys "
        "--markdown` from the tables that read, check and echo the settings; a range is "
        "checked the same way by the library, the tool and the Python package. Agent "
        "types are addressed by name: `types.<name>.<key>`.\n\n");
  }
  for (const KeySection& section : sections) {
    if (!args.command.empty() && section.command != args.command) continue;
    PrintSection(section, args.markdown);
    any = true;
  }
  if (!any) {
    throw InputError(fmt::format(
        "keys: unknown command '{}' (run, study, control, fill-gaps, evaluate-gaps, sweep)",
        args.command));
  }
}

}  // namespace

void AddKeysCommand(CLI::App& app) {
  auto args = std::make_shared<KeysArgs>();
  CLI::App* cmd = app.add_subcommand(
      "keys", "Every scenario key (type, default, range, unit, help) of every command, or of one");
  cmd->add_option("command", args->command, "Only this command's keys");
  cmd->add_flag("--markdown", args->markdown, "Write the reference as Markdown (docs/keys.md)");
  cmd->callback([args] { PrintKeys(*args); });
}

}  // namespace moreau::cli
