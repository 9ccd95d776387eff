// [forces] of the particle scenario (`moreau run`, problem.kind = "particles", with or without
// agent [[types]]): its keys, and the keys holding a vector of the problem's dimension, which
// [forces] and the geometry keys of particles_scenario.cpp share.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "field_table.h"
#include "run/particles_scenario.h"
#include "scenario.h"

namespace moreau::cli {

// A key holding k numbers (k: the problem's dimension); empty when absent (the key still counts
// as known). Throws InputError when the key holds another count of numbers.
std::optional<particles::Vec3> ReadVec(Scenario& sc, const std::string& key, int k);

// The first k entries as a JSON array (null for an empty optional).
nlohmann::json EchoVec(const particles::Vec3& v, int k);
nlohmann::json EchoVec(const std::optional<particles::Vec3>& v, int k);

// A key of the problem's dimension; `ref` reaches a Vec3 or an optional Vec3 member.
template <class A>
void AddVec(FieldTable<ParticleScenario>& t, std::string key, A ref, std::string help) {
  t.Custom(
      std::move(key), "k numbers",
      [ref](Scenario& sc, ParticleScenario& s, const std::string& k) {
        if (const std::optional<particles::Vec3> v = ReadVec(sc, k, s.dimension)) {
          std::invoke(ref, s) = *v;
        }
      },
      [ref](const ParticleScenario& s) { return EchoVec(std::invoke(ref, s), s.dimension); },
      std::move(help));
}

// forces.*: the scalar keys in one sub-table mounted under "forces" (with the check that a
// crowd's speed spread σ_v is at most propulsion_speed / 3), then the vector keys.
void AddForceFields(FieldTable<ParticleScenario>& table);

}  // namespace moreau::cli
