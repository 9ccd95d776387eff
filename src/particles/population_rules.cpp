// PopulationRules and PopulationSummary: validation, names, JSON; the daughter id.
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

std::string_view DivisionAxisName(DivisionAxis axis) {
  return axis == DivisionAxis::kRandom ? "random" : "polarity";
}

DivisionAxis ParseDivisionAxis(std::string_view name) {
  if (name == "random") return DivisionAxis::kRandom;
  if (name == "polarity") return DivisionAxis::kPolarity;
  throw InputError(fmt::format("unknown division axis '{}' (expected random or polarity)", name));
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

namespace {

void CheckNonNegative(std::size_t t, const char* field, double v) {
  if (!(v >= 0.0) || !std::isfinite(v)) {
    throw InputError(fmt::format("types[{}].{} must be ≥ 0 (got {})", t, field, v));
  }
}

void ValidateType(std::size_t t, const AgentType& a) {
  if (a.name.empty()) throw InputError(fmt::format("types[{}].name must not be empty", t));
  if (!(a.radius > 0.0) || !std::isfinite(a.radius)) {
    throw InputError(fmt::format("types[{}].radius must be > 0 (got {})", t, a.radius));
  }
  if (!(a.mobility > 0.0) || !std::isfinite(a.mobility)) {
    throw InputError(fmt::format("types[{}].mobility must be > 0 (got {})", t, a.mobility));
  }
  CheckNonNegative(t, "growth_rate", a.growth_rate);
  CheckNonNegative(t, "division_radius", a.division_radius);
  CheckNonNegative(t, "cycle_time", a.cycle_time);
  CheckNonNegative(t, "division_rate", a.division_rate);
  CheckNonNegative(t, "death_rate", a.death_rate);
  CheckNonNegative(t, "speed", a.speed);
  CheckNonNegative(t, "persistence_time", a.persistence_time);
  CheckNonNegative(t, "alignment", a.alignment);
  CheckNonNegative(t, "velocity_alignment", a.velocity_alignment);
  CheckNonNegative(t, "max_contacts", a.max_contacts);
  if (a.division_radius > 0.0 && !(a.division_radius > a.radius)) {
    throw InputError(fmt::format("types[{}].division_radius ({}) must be > the radius ({})", t,
                                 a.division_radius, a.radius));
  }
}

}  // namespace

void PopulationRules::Validate() const {
  if (types.empty()) throw InputError("types: a population needs at least one agent type");
  std::set<std::string_view> names;
  for (std::size_t t = 0; t < types.size(); ++t) {
    ValidateType(t, types[t]);
    if (!names.insert(types[t].name).second) {
      throw InputError(fmt::format("types: the name '{}' is used twice", types[t].name));
    }
  }
  if (interval < 1) throw InputError(fmt::format("interval must be ≥ 1 (got {})", interval));
  if (exit && exit->normal == Vec3{0.0, 0.0, 0.0}) {
    throw InputError("exit.normal must be non-zero");
  }
  if (!(contact_factor >= 1.0 && contact_factor <= 1.5)) {
    throw InputError(fmt::format("contact_factor must be in [1, 1.5] (got {})", contact_factor));
  }
  if (!(relax_tolerance > 0.0)) {
    throw InputError(fmt::format("relax_tolerance must be > 0 (got {})", relax_tolerance));
  }
  if (relax_max_sweeps < 1) {
    throw InputError(fmt::format("relax_max_sweeps must be ≥ 1 (got {})", relax_max_sweeps));
  }
  if (max_count < 0) throw InputError(fmt::format("max_count must be ≥ 0 (got {})", max_count));
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
  for (const AgentType& a : types) {
    j["types"].push_back({{"name", a.name},
                          {"radius", a.radius},
                          {"growth_rate", a.growth_rate},
                          {"division_radius", a.division_radius},
                          {"cycle_time", a.cycle_time},
                          {"division_rate", a.division_rate},
                          {"death_rate", a.death_rate},
                          {"mobility", a.mobility},
                          {"speed", a.speed},
                          {"persistence_time", a.persistence_time},
                          {"alignment", a.alignment},
                          {"velocity_alignment", a.velocity_alignment},
                          {"max_contacts", a.max_contacts}});
  }
  j["interval"] = interval;
  j["seed"] = seed;
  j["axis"] = DivisionAxisName(axis);
  if (exit) j["exit"] = {{"normal", exit->normal}, {"offset", exit->offset}};
  j["contact_factor"] = contact_factor;
  j["relax"] = relax;
  j["relax_tolerance"] = relax_tolerance;
  j["relax_max_sweeps"] = relax_max_sweeps;
  j["max_count"] = max_count;
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
