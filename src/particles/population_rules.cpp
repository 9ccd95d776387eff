// PopulationRules and PopulationSummary: validation, names, JSON; the daughter id; the adhesion
// matrix and the segregation index.
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

std::string_view DivisionAxisName(DivisionAxis axis) { return EnumName(kDivisionAxisNames, axis); }

DivisionAxis ParseDivisionAxis(std::string_view name) {
  return ParseEnumName(kDivisionAxisNames, name, "division axis");
}

std::int64_t ChildId(std::int64_t mother_id, int count) {
  // SplitMix64's finaliser (a bijection of 64-bit words) of (id, count), cut to 62 bits.
  std::uint64_t z = static_cast<std::uint64_t>(mother_id) * 0x9E3779B97F4A7C15ULL +
                    static_cast<std::uint64_t>(count) * 0xD1B54A32D192ED03ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<std::int64_t>(z >> 2);
}

const FieldList<AgentType>& AgentType::Fields() {
  using A = AgentType;
  static const FieldList<A> list = [] {
    const Range rate = Range::NonNegative();
    FieldList<A> t;
    t.Text("name", &A::name, "unique among the types")
        .Number("radius", &A::radius, Range::Positive(), "length",
                "r_0: initial agents' and daughters' radius")
        .Number("growth_rate", &A::growth_rate, rate, "length/time", "g: dr/dt")
        .Number("division_radius", &A::division_radius, rate, "length",
                "r_div: divides at r ≥ r_div (0: never by size; else > radius)")
        .Number("cycle_time", &A::cycle_time, rate, "time", "τ_c: divides at age ≥ τ_c (0: never)")
        .Number("division_rate", &A::division_rate, rate, "1/time", "λ: divides at rate λ")
        .Number("death_rate", &A::death_rate, rate, "1/time", "δ: dies at rate δ")
        .Number("mobility", &A::mobility, Range::Positive(), "", "μ, the engine's mobility")
        .Number("speed", &A::speed, rate, "length/time", "v0: motility along the polarity")
        .Number("persistence_time", &A::persistence_time, rate, "time",
                "τ_p: polarity rotational diffusion 1/τ_p (0: none)")
        .Number("alignment", &A::alignment, rate, "1/time",
                "J: alignment with touching agents' polarity")
        .Number("velocity_alignment", &A::velocity_alignment, rate, "1/time",
                "β: alignment with the own velocity")
        .Number("max_contacts", &A::max_contacts, Range::Closed(0.0, 1000.0), "",
                "c_max: grows and divides only while touching fewer (0: no inhibition)")
        .Rule("name", [](const A& a) { return a.name.empty() ? "must not be empty" : ""; })
        .Rule("max_contacts", [](const A& a) {
          return a.max_contacts == std::floor(a.max_contacts)
                     ? std::string()
                     : fmt::format("must be a whole number of contacts (got {})", a.max_contacts);
        })
        .Rule("division_radius", [](const A& a) {
          return a.division_radius > 0.0 && !(a.division_radius > a.radius)
                     ? fmt::format("must be > the radius {} (got {})", a.radius, a.division_radius)
                     : std::string();
        });
    return t;
  }();
  return list;
}

const FieldList<PopulationRules>& PopulationRules::Fields() {
  using P = PopulationRules;
  static const FieldList<P> list = [] {
    FieldList<P> t;
    t.Integer("interval", &P::interval, Range::AtLeast(1), "steps", "engine steps per rule step")
        .Integer("seed", &P::seed, Range::Any(), "", "key of the rules' randomness")
        .Choice("axis", &P::axis, kDivisionAxisNames, "division axis")
        .Number("contact_factor", &P::contact_factor, Range::Closed(1.0, 1.5), "",
                "touching: distance ≤ factor · (r_i + r_j)")
        .Flag("relax", &P::relax, "project after every rule step until overlaps ≤ tolerance")
        .Number("relax_tolerance", &P::relax_tolerance, Range::Positive(), "× min radius",
                "overlap left by the relaxation")
        .Integer("relax_max_sweeps", &P::relax_max_sweeps, Range::AtLeast(1), "",
                 "relaxation sweeps at most")
        .Integer("max_count", &P::max_count, Range::NonNegative(), "",
                 "stop at this count (0: none)");
    return t;
  }();
  return list;
}

void PopulationRules::Validate() const {
  if (types.empty()) throw InputError("types", "a population needs at least one agent type");
  std::set<std::string_view> names;
  for (const AgentType& type : types) {
    try {
      AgentType::Fields().Validate(type);
    } catch (const InputError& e) {
      throw e.Under(type.name.empty() ? "types" : "types." + type.name);
    }
    if (!names.insert(type.name).second) {
      throw InputError("types", fmt::format("the name '{}' is used twice", type.name));
    }
  }
  std::set<std::string_view> variable_names;
  for (const AgentVariable& v : variables) {
    if (v.name.empty()) throw InputError("variables", "a variable needs a name");
    if (!variable_names.insert(v.name).second) {
      throw InputError("variables", fmt::format("the name '{}' is used twice", v.name));
    }
    if (!std::isfinite(v.initial)) {
      throw InputError("variables." + v.name + ".initial",
                       fmt::format("must be finite (got {})", v.initial));
    }
  }
  Fields().Validate(*this);
  ValidateAdhesion();
  if (exit && exit->normal == Vec3{0.0, 0.0, 0.0}) {
    throw InputError("exit.normal", "must be non-zero");
  }
}

void PopulationRules::ValidateAdhesion() const {
  for (const auto& [pair, k] : adhesion) {
    const std::string key = "adhesion." + pair.first + "." + pair.second;
    try {
      (void)TypeIndex(pair.first);
      (void)TypeIndex(pair.second);
    } catch (const InputError& e) {
      throw InputError(key, e.what());
    }
    if (!(k >= 0.0) || !std::isfinite(k)) {
      throw InputError(key, fmt::format("must be ≥ 0 and finite (got {})", k));
    }
    const auto mirror = adhesion.find({pair.second, pair.first});
    if (mirror != adhesion.end() && mirror->second != k) {
      throw InputError(key, fmt::format("({}) differs from adhesion.{}.{} ({}): a pair has one "
                                        "adhesion, give it once",
                                        k, pair.second, pair.first, mirror->second));
    }
  }
}

Forces PopulationRules::WithAdhesion(Forces forces) const {
  if (adhesion.empty()) return forces;
  if (!forces.attraction || !(forces.attraction->range > 0.0)) {
    throw InputError("adhesion", "needs the attraction's range ℓ > 0 (forces.attraction_range)");
  }
  const std::size_t c = types.size();
  std::vector<double>& K = forces.attraction->class_stiffness;
  K.assign(c * c, forces.attraction->stiffness);
  for (const auto& [pair, k] : adhesion) {
    const auto a = static_cast<std::size_t>(TypeIndex(pair.first));
    const auto b = static_cast<std::size_t>(TypeIndex(pair.second));
    K[a * c + b] = k;
    K[b * c + a] = k;
  }
  return forces;
}

double SegregationIndex(std::span<const int> types, std::span<const std::pair<int, int>> contacts) {
  std::vector<int> touching(types.size(), 0), alike(types.size(), 0);
  for (const auto& [i, j] : contacts) {
    const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
    const int same = types[ui] == types[uj] ? 1 : 0;
    ++touching[ui];
    ++touching[uj];
    alike[ui] += same;
    alike[uj] += same;
  }
  double sum = 0.0;
  std::int64_t counted = 0;
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (touching[i] == 0) continue;
    sum += static_cast<double>(alike[i]) / touching[i];
    ++counted;
  }
  return counted > 0 ? sum / static_cast<double>(counted) : 0.0;
}

int PopulationRules::TypeIndex(std::string_view name) const {
  std::string known;
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (types[t].name == name) return static_cast<int>(t);
    known += (t > 0 ? ", " : "") + types[t].name;
  }
  throw InputError(fmt::format("unknown type '{}' (types: {})", name, known));
}

nlohmann::json PopulationRules::ToJson() const {
  nlohmann::json j;
  for (const AgentType& a : types) j["types"].push_back(AgentType::Fields().ToJson(a));
  j["interval"] = interval;
  j["seed"] = seed;
  j["axis"] = DivisionAxisName(axis);
  if (exit) j["exit"] = {{"normal", exit->normal}, {"offset", exit->offset}};
  j["contact_factor"] = contact_factor;
  j["relax"] = relax;
  j["relax_tolerance"] = relax_tolerance;
  j["relax_max_sweeps"] = relax_max_sweeps;
  j["max_count"] = max_count;
  for (const auto& [pair, k] : adhesion) j["adhesion"][pair.first][pair.second] = k;
  for (const AgentVariable& v : variables) {
    j["variables"].push_back({{"name", v.name},
                              {"initial", v.initial},
                              {"inherit", EnumName(kInheritanceNames, v.inherit)}});
  }
  return j;
}

nlohmann::json PopulationSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["rule_steps"] = rule_steps;
  j["births"] = births;
  j["deaths"] = deaths;
  j["removals"] = removals;
  j["relax_sweeps"] = relax_sweeps;
  j["final_count"] = final_count;
  j["max_overlap_before"] = max_overlap_before;
  j["rules_seconds"] = rules_seconds;
  j["engine"] = engine.ToJson();
  j["settings"] = settings.ToJson();
  return j;
}

}  // namespace moreau::particles
