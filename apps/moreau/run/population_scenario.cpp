#include "run/population_scenario.h"

#include <cmath>
#include <functional>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {
namespace {

using S = ParticleScenario;
using particles::AgentType;

// The numeric fields of one [[types]] table, by key.
const std::vector<std::pair<const char*, double AgentType::*>>& TypeNumbers() {
  static const std::vector<std::pair<const char*, double AgentType::*>> fields = {
      {"radius", &AgentType::radius},
      {"growth_rate", &AgentType::growth_rate},
      {"division_radius", &AgentType::division_radius},
      {"cycle_time", &AgentType::cycle_time},
      {"division_rate", &AgentType::division_rate},
      {"death_rate", &AgentType::death_rate},
      {"mobility", &AgentType::mobility},
      {"speed", &AgentType::speed},
      {"persistence_time", &AgentType::persistence_time},
      {"alignment", &AgentType::alignment},
      {"velocity_alignment", &AgentType::velocity_alignment},
      {"max_contacts", &AgentType::max_contacts}};
  return fields;
}

AgentType ReadType(const Scenario& sc, const std::string& at, const toml::table& t) {
  AgentType a;
  for (const auto& [key, node] : t) {
    const std::string field(key.str());
    if (field == "name") {
      const auto name = node.value<std::string>();
      if (!name) sc.Fail(at + ".name", "expected a string");
      a.name = *name;
      continue;
    }
    const auto& numbers = TypeNumbers();
    const auto it = std::find_if(numbers.begin(), numbers.end(),
                                 [&](const auto& f) { return field == f.first; });
    if (it == numbers.end()) sc.Fail(at + "." + field, "unknown key");
    const auto v = node.value<double>();
    if (!v || !std::isfinite(*v)) sc.Fail(at + "." + field, "expected a finite number");
    a.*(it->second) = *v;
  }
  if (!t.contains("name")) sc.Fail(at + ".name", "required key is missing");
  return a;
}

void ReadTypes(Scenario& sc, S& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) sc.Fail(key, "expected an array of tables ([[types]])");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table* t = (*arr)[i].as_table();
    if (t == nullptr) sc.Fail(key, "expected an array of tables ([[types]])");
    s.population.rules.types.push_back(ReadType(sc, fmt::format("{}[{}]", key, i), *t));
  }
}

nlohmann::json EchoTypes(const S& s) {
  if (!s.is_population()) return nullptr;
  return s.population.rules.ToJson()["types"];
}

// initial.types: one name, or one name per agent.
void ReadInitialTypes(Scenario& sc, S& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  if (const auto one = node->value<std::string>()) {
    s.population.initial_types = {*one};
    return;
  }
  const toml::array* arr = node->as_array();
  if (arr == nullptr) sc.Fail(key, "expected a type name or an array of names");
  for (const toml::node& item : *arr) {
    const auto name = item.value<std::string>();
    if (!name) sc.Fail(key, "expected type names (strings)");
    s.population.initial_types.push_back(*name);
  }
}

void AddRuleFields(FieldTable<S>& t) {
  using P = particles::PopulationRules;
  FieldTable<P> sub;
  sub.Integer("interval", &P::interval, Range::AtLeast(1), "engine steps per rule step")
      .Choice("axis", &P::axis, particles::ParseDivisionAxis, particles::DivisionAxisName,
              "random, polarity", "division axis")
      .Number("contact_factor", &P::contact_factor, Range::Closed(1.0, 1.5),
              "touching: distance ≤ factor · (r_i + r_j)")
      .Flag("relax", &P::relax, "project after every rule step until overlaps ≤ tolerance")
      .Number("relax_tolerance", &P::relax_tolerance, Range::Positive(), "× the smallest radius")
      .Integer("relax_max_sweeps", &P::relax_max_sweeps, Range::AtLeast(1), "sweeps at most")
      .Integer("max_count", &P::max_count, Range::NonNegative(), "stop at this count (0: none)");
  t.Mount(
      "population", [](auto& s) -> auto& { return s.population.rules; }, sub);
}

}  // namespace

void AddPopulationFields(FieldTable<S>& t) {
  t.Custom("types", "[[types]] name, radius, …", ReadTypes, EchoTypes,
           "agent types: an agent-based model (docs/abm.md)");
  AddRuleFields(t);
  t.Integer(
       "population.record_every", [](auto& s) -> auto& { return s.population.record_every; },
       Range::AtLeast(1), "rule steps between rows of population.csv")
      .OptionalNumber(
          "population.exit_offset", [](auto& s) -> auto& { return s.population.exit_offset; },
          Range::Any(), "agents with ⟨exit_normal, X⟩ > exit_offset are removed");
  t.Custom(
       "population.exit_normal", "k numbers",
       [](Scenario& sc, S& s, const std::string& k) {
         const std::vector<double> v = sc.GetDoubleArray(k, {});
         if (v.empty()) return;
         if (static_cast<int>(v.size()) != s.dimension) {
           sc.Fail(k, fmt::format("expected {} numbers (the dimension)", s.dimension));
         }
         std::copy(v.begin(), v.end(), s.population.exit_normal.begin());
       },
       [](const S& s) {
         return nlohmann::json(std::vector<double>(s.population.exit_normal.begin(),
                                                   s.population.exit_normal.begin() + s.dimension));
       },
       "normal of the exit plane")
      .Custom(
          "initial.types", "name or names", ReadInitialTypes,
          [](const S& s) { return nlohmann::json(s.population.initial_types); },
          "type of every agent (default: the first type)");
  t.Check("types", [](const S& s) {
     if (s.is_population()) s.MakeRules().Validate();
   }).Check("initial.types", [](const S& s) {
    if (!s.is_population()) {
      if (!s.population.initial_types.empty()) throw InputError("needs [[types]]");
      return;
    }
    (void)s.InitialTypes();
  });
}

particles::PopulationRules ParticleScenario::MakeRules() const {
  particles::PopulationRules rules = population.rules;
  rules.seed = static_cast<std::uint64_t>(seed);
  if (population.exit_offset) {
    rules.exit = particles::ExitPlane{population.exit_normal, *population.exit_offset};
  }
  return rules;
}

std::vector<int> ParticleScenario::InitialTypes() const {
  const std::vector<std::string>& names = population.initial_types;
  const auto n = static_cast<std::size_t>(count);
  if (names.size() > 1 && names.size() != n) {
    throw InputError(
        fmt::format("{} names for {} agents (give one name, or problem.count)", names.size(), n));
  }
  std::vector<int> types(n, 0);
  for (std::size_t i = 0; i < n && !names.empty(); ++i) {
    types[i] = population.rules.TypeIndex(names[names.size() == 1 ? 0 : i]);
  }
  return types;
}

}  // namespace moreau::cli
