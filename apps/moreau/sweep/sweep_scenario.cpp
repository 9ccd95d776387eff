#include "sweep/sweep_scenario.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "field_table.h"
#include "moreau/common/error.h"
#include "moreau/common/input_file.h"
#include "moreau/common/memory.h"

namespace moreau::cli {
namespace {

namespace fs = std::filesystem;

// A value as a TOML literal that reads back to the same value: floats in their shortest
// round-trip form, kept floats ("1.0", not "1").
std::string TomlLiteral(const toml::node& node) {
  if (const auto v = node.value_exact<double>()) {
    std::string text = fmt::format("{}", *v);
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
    return text;
  }
  std::ostringstream out;
  node.visit([&](const auto& n) { out << n; });
  return out.str();
}

// The leaves of a (nested) table in the order they are written in the file, as dotted keys.
void CollectLeaves(const toml::table& table, const std::string& prefix,
                   std::vector<std::pair<std::string, const toml::node*>>* leaves) {
  for (const auto& [k, node] : table) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = node.as_table()) {
      CollectLeaves(*sub, key, leaves);
    } else {
      leaves->emplace_back(key, &node);
    }
  }
}

std::vector<std::pair<std::string, const toml::node*>> LeavesInFileOrder(Scenario& file,
                                                                         const std::string& key) {
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  const toml::node* node = file.GetNode(key);
  if (node == nullptr) return leaves;
  const toml::table* table = node->as_table();
  if (table == nullptr) file.Fail(key, "expected a table of scenario keys");
  CollectLeaves(*table, "", &leaves);
  std::stable_sort(leaves.begin(), leaves.end(), [](const auto& a, const auto& b) {
    const toml::source_position pa = a.second->source().begin, pb = b.second->source().begin;
    return std::tie(pa.line, pa.column) < std::tie(pb.line, pb.column);
  });
  return leaves;
}

void ReadAxes(Scenario& file, SweepScenario& s, const std::string& key) {
  for (const auto& [axis_key, node] : LeavesInFileOrder(file, key)) {
    const toml::array* values = node->as_array();
    if (values == nullptr) file.Fail(key + "." + axis_key, "expected an array of values");
    sweep::Axis axis{axis_key, {}};
    for (const toml::node& v : *values) axis.values.push_back(TomlLiteral(v));
    s.grid.axes.push_back(std::move(axis));
  }
}

void ReadSeeds(Scenario& file, SweepScenario& s, const std::string& key) {
  const toml::node* node = file.GetNode(key);
  if (node == nullptr) return;
  if (const auto n = node->value_exact<std::int64_t>()) {
    if (*n < 1 || *n > sweep::Grid::kMaxRuns) {
      file.Fail(key, fmt::format("must be ≥ 1 and ≤ {} (got {})", sweep::Grid::kMaxRuns, *n));
    }
    WithKey(file, key, [&] {
      CheckMemory(fmt::format("{} runs", *n), sweep::Grid::kBytesPerRun * static_cast<double>(*n));
    });
    for (std::int64_t seed = 1; seed <= *n; ++seed) s.grid.seeds.push_back(seed);
    return;
  }
  const toml::array* list = node->as_array();
  if (list == nullptr || list->empty()) file.Fail(key, "expected a count N (seeds 1…N) or a list");
  for (const toml::node& v : *list) {
    const auto seed = v.value_exact<std::int64_t>();
    if (!seed) file.Fail(key, "seeds must be integers");
    s.grid.seeds.push_back(*seed);
  }
}

void ReadCollect(Scenario& file, SweepScenario& s, const std::string& key) {
  const toml::node* node = file.GetNode(key);
  if (node == nullptr) return;
  const toml::array* list = node->as_array();
  if (list == nullptr) file.Fail(key, "expected an array of summary keys");
  for (const toml::node& v : *list) {
    const auto name = v.value_exact<std::string>();
    if (!name || name->empty()) file.Fail(key, "expected non-empty strings (summary keys)");
    s.collect.push_back(*name);
  }
}

const FieldTable<SweepScenario>& SweepFields() {
  static const FieldTable<SweepScenario> table = [] {
    FieldTable<SweepScenario> t;
    t.Text("command", &SweepScenario::command, "the command every run is: run, control, fill-gaps")
        .Required()
        .Text("scenario", &SweepScenario::scenario,
              "base scenario file, relative to the sweep file (fill-gaps: optional settings)")
        .Text("recording", &SweepScenario::recording, "fill-gaps: the recording")
        .Choice(
            "combine", [](auto& s) -> auto& { return s.grid.combination; }, sweep::ParseCombination,
            sweep::CombinationName, "cross, zip", "how the axes combine")
        .Text(
            "seed_key", [](auto& s) -> auto& { return s.grid.seed_key; },
            "the scenario key the seeds set")
        .Custom(
            "seeds", "integer or array", ReadSeeds,
            [](const SweepScenario& s) { return nlohmann::json(s.grid.seeds); },
            "N (seeds 1…N) or a list; every point runs once per seed")
        .Custom(
            "collect", "array of strings", ReadCollect,
            [](const SweepScenario& s) { return nlohmann::json(s.collect); },
            "dotted keys of each run's summary.json to tabulate")
        .Flag("run_folders", &SweepScenario::run_folders, "write DIR/runs/<hash>/ for every run")
        .Custom(
            "set", "table",
            [](Scenario& file, SweepScenario& s, const std::string& key) {
              for (const auto& [k, node] : LeavesInFileOrder(file, key)) {
                s.fixed.push_back({k, TomlLiteral(*node)});
              }
            },
            [](const SweepScenario& s) {
              nlohmann::json j = nlohmann::json::object();
              for (const sweep::Setting& f : s.fixed) j[f.key] = LiteralCell(f.value);
              return j;
            },
            "overrides of the base scenario for every run")
        .Custom(
            "axes", "table of arrays", ReadAxes,
            [](const SweepScenario& s) {
              nlohmann::json j = nlohmann::json::object();
              for (const sweep::Axis& a : s.grid.axes) {
                for (const std::string& v : a.values) j[a.key].push_back(LiteralCell(v));
              }
              return j;
            },
            "scenario keys and their values")
        .Check("command", [](const SweepScenario& s) {
          if (s.command != "run" && s.command != "control" && s.command != "fill-gaps") {
            throw InputError(
                fmt::format("unknown command '{}' (run, control, fill-gaps)", s.command));
          }
        });
    return t;
  }();
  return table;
}

std::string ReadBytes(Scenario& file, const std::string& key, const std::string& path) {
  if (const std::string why = NotAnInputFile(path); !why.empty()) {
    file.Fail(key, fmt::format("cannot read {}: it {}", path, why));
  }
  return ReadInputFile(path);
}

}  // namespace

std::vector<KeyRow> SweepKeys() { return SweepFields().Rows(SweepScenario{}); }

std::vector<std::string> SweepScenario::Overrides(std::int64_t index) const {
  std::vector<std::string> overrides;
  for (const sweep::Setting& f : fixed) overrides.push_back(f.key + "=" + f.value);
  for (const sweep::Setting& r : grid.Run(index)) overrides.push_back(r.key + "=" + r.value);
  return overrides;
}

SweepScenario ReadSweepScenario(Scenario& file) {
  SweepScenario s;
  SweepFields().Read(file, s);
  WithKey(file, "axes", [&] { s.grid.Validate(); });
  const fs::path folder = fs::path(file.path()).parent_path();
  const auto resolve = [&](std::string& path) {
    if (!path.empty() && fs::path(path).is_relative()) path = (folder / path).lexically_normal();
  };
  resolve(s.scenario);
  resolve(s.recording);
  if (s.command == "fill-gaps" && s.recording.empty()) {
    file.Fail("recording", "required key is missing (command = \"fill-gaps\")");
  }
  if (s.command != "fill-gaps" && s.scenario.empty()) {
    file.Fail("scenario", "required key is missing");
  }
  s.context = fmt::format("command={}\nrecording={}\ncollect={}\n", s.command, s.recording,
                          nlohmann::json(s.collect).dump());
  if (!s.scenario.empty()) s.context += ReadBytes(file, "scenario", s.scenario);
  for (const sweep::Setting& f : s.fixed) s.context += fmt::format("\n{}={}", f.key, f.value);
  return s;
}

nlohmann::json EchoSweepScenario(const SweepScenario& sweep) { return SweepFields().Echo(sweep); }

nlohmann::json LiteralCell(const std::string& literal) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + literal);
  } catch (const toml::parse_error&) {
    return literal;
  }
  const toml::node& v = *parsed.get("v");
  if (const auto i = v.value_exact<std::int64_t>()) return *i;
  if (const auto d = v.value_exact<double>()) return *d;
  if (const auto b = v.value_exact<bool>()) return *b;
  if (const auto t = v.value_exact<std::string>()) return *t;
  return literal;
}

}  // namespace moreau::cli
