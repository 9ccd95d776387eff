#include "run/population_scenario.h"

#include <cmath>
#include <functional>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "run/fields_scenario.h"

namespace moreau::cli {
namespace {

using PS = ParticleScenario;
using particles::AgentType;

// One [[types]] table (the keys of AgentType::Fields()); errors name the key as --set does,
// types.<name>.<key> (types[i].<key> while the type has no name).
// A table inside the entry is the type's response to a substrate (run/fields_scenario.h).
AgentType ReadType(const Scenario& sc, const std::string& at, const toml::table& t,
                   FieldSettings* fields) {
  AgentType a;
  if (!t.contains("name")) sc.Fail(at + ".name", "required key is missing");
  const std::string why = AgentType::Fields().Find("name")->set(a, NodeToJson(*t.get("name")));
  if (!why.empty()) sc.Fail(at + ".name", why);
  const std::string prefix = "types." + a.name;
  for (const auto& [key, node] : t) {
    const std::string field(key.str());
    if (const toml::table* sub = node.as_table(); sub != nullptr) {
      ReadSubstrateResponse(sc, a.name, field, *sub, fields);
      continue;
    }
    const auto* f = AgentType::Fields().Find(field);
    if (f == nullptr) sc.Fail(prefix + "." + field, "unknown key");
    const std::string reason = f->set(a, NodeToJson(node));
    if (!reason.empty()) sc.Fail(prefix + "." + field, reason);
  }
  return a;
}

void ReadTypes(Scenario& sc, PS& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) sc.Fail(key, "expected an array of tables ([[types]])");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table* t = (*arr)[i].as_table();
    if (t == nullptr) sc.Fail(key, "expected an array of tables ([[types]])");
    s.population.rules.types.push_back(
        ReadType(sc, fmt::format("{}[{}]", key, i), *t, &s.fields));
  }
}

// The types' keys, each with its responses to the substrates (types.<type>.<substrate>.*).
nlohmann::json EchoTypes(const PS& s) {
  if (!s.is_population()) return nullptr;
  nlohmann::json types = s.population.rules.ToJson()["types"];
  for (nlohmann::json& type : types) {
    for (const particles::SubstrateResponse& r : s.fields.coupling.responses) {
      if (type["name"] == r.type) type[r.substrate] = particles::SubstrateResponse::Fields().ToJson(r);
    }
  }
  return types;
}

// initial.types: one name, or one name per agent.
void ReadInitialTypes(Scenario& sc, PS& s, const std::string& key) {
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

// [population.adhesion]: `a.b = k` (a table per type a, a number per type b); errors name
// population.adhesion.a.b. The names are checked against the types by PopulationRules.
void ReadAdhesion(Scenario& sc, PS& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::table* table = node->as_table();
  if (table == nullptr) sc.Fail(key, "expected a table of type pairs (a.b = stiffness)");
  for (const auto& [a, row] : *table) {
    const std::string at = key + "." + std::string(a.str());
    const toml::table* entries = row.as_table();
    if (entries == nullptr) sc.Fail(at, "expected a table: <type>.<type> = stiffness");
    for (const auto& [b, value] : *entries) {
      const std::string pair = at + "." + std::string(b.str());
      const auto k = value.value<double>();
      if (!k) sc.Fail(pair, "expected a number (the stiffness k_ab)");
      CheckRange(sc, pair, Range::NonNegative(), *k, fmt::format("{}", *k));
      s.population.rules.adhesion[{std::string(a.str()), std::string(b.str())}] = *k;
    }
  }
}

nlohmann::json EchoAdhesion(const PS& s) {
  const nlohmann::json j = s.population.rules.ToJson();
  return j.contains("adhesion") ? j["adhesion"] : nlohmann::json();
}

void AddRuleFields(FieldTable<PS>& t) {
  // population.seed is not a key: the rules take problem.seed (MakeRules).
  t.Mount("population", [](auto& s) -> auto& { return s.population.rules; },
          particles::PopulationRules::Fields(), {{"seed", ""}});
  t.Custom("population.adhesion", "<a>.<b> = number ≥ 0 (force/length)", ReadAdhesion, EchoAdhesion,
           "k_ab: the attraction's stiffness between types a and b (differential adhesion); "
           "pairs not given: forces.attraction_stiffness; range forces.attraction_range")
      .Check("population.adhesion", [](const PS& s) {
        if (s.population.rules.adhesion.empty()) return;
        if (!s.is_population()) throw InputError("needs [[types]]");
        if (!s.forces.attraction_range) {
          throw InputError("needs forces.attraction_range (the range ℓ of the adhesion)");
        }
      });
}

}  // namespace

void AddPopulationFields(FieldTable<PS>& t) {
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
       [](Scenario& sc, PS& s, const std::string& k) {
         const std::vector<double> v = sc.GetDoubleArray(k, {});
         if (v.empty()) return;
         if (static_cast<int>(v.size()) != s.dimension) {
           sc.Fail(k, fmt::format("expected {} numbers (the dimension)", s.dimension));
         }
         std::copy(v.begin(), v.end(), s.population.exit_normal.begin());
       },
       [](const PS& s) {
         return nlohmann::json(std::vector<double>(s.population.exit_normal.begin(),
                                                   s.population.exit_normal.begin() + s.dimension));
       },
       "normal of the exit plane")
      .Custom(
          "initial.types", "name or names", ReadInitialTypes,
          [](const PS& s) { return nlohmann::json(s.population.initial_types); },
          "type of every agent, or a list repeated over the agents (default: the first type)");
  t.Check("", [](const PS& s) {
     if (!s.is_population()) return;
     try {
       s.MakeRules().Validate();
     } catch (const InputError& e) {  // the adhesion's keys are population.adhesion.<a>.<b>
       if (e.key().starts_with("adhesion")) throw e.Under("population");
       throw;
     }
   }).Check("initial.types", [](const PS& s) {
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
  if (!names.empty() && n % names.size() != 0) {
    throw InputError(fmt::format(
        "{} names for {} agents (give one name, one per agent, or a list whose length divides "
        "problem.count)",
        names.size(), n));
  }
  // A shorter list repeats: agent i gets names[i mod m].
  std::vector<int> types(n, 0);
  for (std::size_t i = 0; i < n && !names.empty(); ++i) {
    types[i] = population.rules.TypeIndex(names[i % names.size()]);
  }
  return types;
}

}  // namespace moreau::cli
