#include "evaluate_gaps/evaluate_gaps_scenario.h"

#include <algorithm>

#include <fmt/format.h>

#include "mocap_settings.h"

namespace moreau::cli {
namespace {

using EG = EvaluateGapsSettings;

// evaluation.methods: an array of names or one comma-separated string ("linear,pca").
void ReadMethods(Scenario& sc, EG& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  std::vector<std::string> names;
  if (const auto text = node->value_exact<std::string>()) {
    for (std::size_t start = 0; start <= text->size();) {
      const std::size_t comma = std::min(text->find(',', start), text->size());
      names.push_back(text->substr(start, comma - start));
      start = comma + 1;
    }
  } else if (const toml::array* array = node->as_array()) {
    for (const toml::node& item : *array) {
      const auto name = item.value_exact<std::string>();
      if (!name) sc.Fail(key, "expected method names (strings)");
      names.push_back(*name);
    }
  } else {
    sc.Fail(key, "expected an array of method names or a comma-separated string");
  }
  std::vector<mocap::GapFillMethod>& methods = s.evaluation.methods;
  methods.clear();
  for (const std::string& name : names) {
    WithKey(sc, key, [&] { methods.push_back(mocap::ParseGapFillMethod(name)); });
    if (std::count(methods.begin(), methods.end(), methods.back()) > 1) {
      sc.Fail(key, fmt::format("method '{}' is named twice", name));
    }
  }
}

nlohmann::json EchoMethods(const EG& s) {
  nlohmann::json names = nlohmann::json::array();
  for (mocap::GapFillMethod m : s.evaluation.methods) names.push_back(mocap::ToString(m));
  return names;
}

}  // namespace

FieldTable<EvaluateGapsSettings> EvaluateGapsFields() {
  FieldTable<EG> t;
  t.Custom("evaluation.methods", "method names", ReadMethods, EchoMethods,
           "methods compared: " + FillMethodNames())
      .Mount(
          "evaluation", [](auto& s) -> auto& { return s.evaluation; },
          mocap::EvaluationOptions::Fields(), {{"methods", ""}})
      .CapThreads("evaluation.threads")
      // Every method's block as fill-gaps names it (the method is evaluation.methods).
      .Mount(
          "", [](auto& s) -> auto& { return s.evaluation.fill; }, mocap::GapFillOptions::Fields(),
          {{"method", ""}, {"max_gap_seconds", "fill.max_gap_seconds"}})
      .CapThreads("ocp.newton.threads")
      .Mount("read", &EG::read, mocap::ReadOptions::Fields());
  return t;
}

EvaluateGapsSettings ReadEvaluateGapsSettings(Scenario& scenario) {
  EvaluateGapsSettings settings;
  EvaluateGapsFields().Read(scenario, settings);
  scenario.CheckAllKeysUsed();
  return settings;
}

nlohmann::json EchoEvaluateGapsSettings(const EvaluateGapsSettings& settings) {
  return EvaluateGapsFields().Echo(settings);
}

}  // namespace moreau::cli
